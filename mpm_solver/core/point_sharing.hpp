// The side of a constitutive law whose points hold heavy state (a live DEM cell each) that lets a run
// spread those points over ranks (ranks.hpp): each point is updated on one rank, its owner, and the
// other ranks answer the solver's questions about it (p_wave_modulus, damage, the DemBackedLaw
// counters) from the summary the owner sends after every update. The full state of a point moves
// only to rank 0 when it writes a restart file or a tracked point's cell, and to a new owner when
// the points are re-dealt by cost.
#pragma once
#include <cstddef>

#include "common/byte_buffer.hpp"

namespace grainbank::mpm {

class PointSharing {
 public:
  virtual ~PointSharing() = default;
  // What the other ranks need of `slot` after its update: small (it goes out every step).
  virtual void write_summary(std::size_t slot, common::ByteWriter& out) const = 0;
  virtual void read_summary(std::size_t slot, common::ByteReader& in) = 0;
  // Everything the slot carries, so that the receiving rank continues it bit for bit.
  virtual void write_point_state(std::size_t slot, common::ByteWriter& out) const = 0;
  virtual void read_point_state(std::size_t slot, common::ByteReader& in) = 0;
  // The point now lives on another rank (its state was sent there): close what this rank held open
  // for it (e.g. a path it was writing to the library).
  virtual void release(std::size_t /*slot*/) {}
};

}  // namespace grainbank::mpm
