// What a nearest-state query takes and gives (lookup_index.hpp). Stress is tension-positive [Pa],
// distances are in key units (state_key.hpp: 1 = "a different state").
#pragma once
#include <cstdint>
#include <limits>

#include "dem_sampler/cell/types.hpp"
#include "database/store/record.hpp"

namespace grainbank::lookup {

// Where an indexed response came from: record `record_index` of path `path_id` (a negative path id
// for records inserted without a library path, e.g. synthetic ones).
struct RecordRef {
  std::int64_t path_id = 0;
  std::int64_t record_index = 0;
  bool operator==(const RecordRef&) const = default;
};

// The kinematic state of a material point (or cell) in the caller's lab frame.
struct LookupState {
  dem::Mat3 F = dem::Mat3::Identity();  // deformation gradient, det F > 0
  dem::Mat3 L = dem::Mat3::Zero();      // velocity gradient [1/s]
  double damage = 0;                    // D = 1 - N_b / N_b(0)
};

// What an indexed record answers: its stress in the material frame, Rᵀ σ R (tension-positive,
// Pa), and the cell measures the MPM needs besides stress.
struct RecordResponse {
  db::Stress6 material_stress{};
  double damage = 0;          // D
  double coordination = 0;    // Z
  double solid_fraction = 0;  // φ
};

struct LookupOptions {
  std::size_t k = 4;       // neighbours blended (at least 1)
  double tolerance = 0.5;  // a hit needs the nearest record within this key distance
};

struct LookupAnswer {
  dem::Mat3 stress = dem::Mat3::Zero();  // R σ̂ Rᵀ in the query's frame; zero when the index is empty
  double distance = std::numeric_limits<double>::infinity();  // to the nearest record
  bool hit = false;                                           // distance <= tolerance
  double estimated_error = 0;  // blend.hpp: spread of the k answers around the blend [Pa]
  double damage = 0, coordination = 0, solid_fraction = 0;  // blended like the stress
  std::size_t neighbours = 0;  // answers blended (< k only when the index holds fewer records)
  RecordRef nearest;           // origin of the nearest record (valid when neighbours > 0)
};

}  // namespace grainbank::lookup
