// How a solver spreads its point updates over ranks (ranks.hpp). The points of a law with a
// PointSharing are dealt out by id (point id mod ranks), so a point stays on its rank however the
// points are sorted; every other point is updated on every rank alike. After each stress update the
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
    return !spread() || !laws[mp.law]->point_sharing() || int(mp.id % std::uint32_t(ranks_->size())) == ranks_->rank();
  }

  // After every rank updated its own points: every spread point as its owner left it. `skipped[p]`
  // tells whether points[p] skipped its constitutive call; returns the number of such skips among
  // the points other ranks updated.
  long share_updates(std::vector<MaterialPoint>& points, const Laws& laws, const std::vector<char>& skipped) const;
  // Each spread point's full law state, from its owner to every rank (`ids` empty: every point).
  void share_point_states(const std::vector<MaterialPoint>& points, const Laws& laws,
                          const std::vector<std::uint32_t>& ids) const;
  // The point with the smallest value among those each rank offers (value, point id), on every rank;
  // ties go to the lower id. {inf, UINT32_MAX} when no rank offers one.
  std::pair<double, std::uint32_t> min_over_ranks(std::pair<double, std::uint32_t> mine) const;
  // Bytes all ranks sent in share_updates so far (each rank receives them all).
  double shared_update_bytes() const { return shared_update_bytes_; }

 private:
  std::shared_ptr<const Ranks> ranks_;
  mutable double shared_update_bytes_ = 0;
};

}  // namespace grainbank::mpm
