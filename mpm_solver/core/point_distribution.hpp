// How a solver spreads its point updates over ranks (ranks.hpp). The points of a law with a
// PointSharing are first dealt out by id (point id mod ranks), so a point stays on its rank however
// the points are sorted, then re-dealt by their measured cost (rebalance); every other point is
// updated on every rank alike. After each stress update the
// owners send what changed (stress, volume, pending motion, the law's summary of the point), so all
// ranks hold the same points to the last bit and the MPM, stepped alike everywhere, stays identical.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mpm_solver/core/constitutive_law.hpp"
#include "mpm_solver/core/material_point.hpp"
#include "mpm_solver/core/ranks.hpp"

namespace grainbank::mpm {

class PointDistribution {
 public:
  using Laws = std::vector<std::unique_ptr<ConstitutiveLaw>>;

  PointDistribution() : ranks_(std::make_shared<OneRank>()) {}
  // Throws std::invalid_argument naming the first law that can neither be replicated nor spread,
  // when there is more than one rank.
  void set_ranks(std::shared_ptr<const Ranks> ranks, const Laws& laws);
  const Ranks& ranks() const { return *ranks_; }
  bool spread() const { return ranks_->size() > 1; }

  // Whether this rank updates the point (always, on one rank).
  bool updates_here(const MaterialPoint& mp, const Laws& laws) const {
    return !spread() || !laws[mp.law]->point_sharing() || owner(mp.id) == ranks_->rank();
  }

  // Deals the spread points out anew by what they cost since the last call (`seconds` by point id:
  // this rank's own points, 0 for the others), when the busiest rank carries over kLoadTolerance more
  // than in the greedy deal (costliest first onto the least-loaded rank): the costliest first, each
  // kept on its rank while that rank stays within the greedy deal's busiest load plus the tolerance,
  // else put onto the least-loaded rank (ties: the lower id, the lower rank), so every rank computes
  // the same deal; then moves the state of every point that changes rank. Returns the number of
  // points moved (collective).
  static constexpr double kLoadTolerance = 0.05;
  std::size_t rebalance(const std::vector<MaterialPoint>& points, const Laws& laws, const std::vector<double>& seconds);
  // Points moved by rebalance so far.
  std::size_t moved_points() const { return moved_points_; }

  // After every rank updated its own points: every spread point as its owner left it. `skipped[p]`
  // tells whether points[p] skipped its constitutive call; returns the number of such skips among
  // the points other ranks updated.
  long share_updates(std::vector<MaterialPoint>& points, const Laws& laws, const std::vector<char>& skipped) const;
  // Each spread point's full law state, from its owner to rank 0 (`ids` empty: every point).
  void gather_point_states(const std::vector<MaterialPoint>& points, const Laws& laws,
                           const std::vector<std::uint32_t>& ids) const;
  // The point with the smallest value among those each rank offers (value, point id), on every rank;
  // ties go to the lower id. {inf, UINT32_MAX} when no rank offers one.
  std::pair<double, std::uint32_t> min_over_ranks(std::pair<double, std::uint32_t> mine) const;
  // Bytes all ranks sent in share_updates so far (each rank receives them all).
  double shared_update_bytes() const { return shared_update_bytes_; }

 private:
  int owner(std::uint32_t id) const {
    return owner_.empty() ? int(id % std::uint32_t(ranks_->size())) : owner_[id];
  }
  // Sends the full state of every spread point `send` accepts from this rank to all (or to rank 0
  // only); reads those of other ranks' points that `receive` accepts.
  template <class Send, class Receive>
  void move_point_states(const std::vector<MaterialPoint>& points, const Laws& laws, Send&& send,
                         Receive&& receive, bool to_root_only) const;

  std::shared_ptr<const Ranks> ranks_;
  std::vector<int> owner_;  // rank of each point id (empty: dealt by id, id mod ranks)
  mutable double shared_update_bytes_ = 0;
  std::size_t moved_points_ = 0;
};

}  // namespace grainbank::mpm
