#include "mpm_solver/core/point_distribution.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "mpm_solver/core/point_sharing.hpp"

namespace grainbank::mpm {

namespace {

// Index in `points` of every point id (points are sorted by cell, not by id).
std::vector<std::uint32_t> index_of_ids(const std::vector<MaterialPoint>& points) {
  std::vector<std::uint32_t> index(points.size());
  for (std::size_t p = 0; p < points.size(); ++p) index.at(points[p].id) = static_cast<std::uint32_t>(p);
  return index;
}

bool spread_point(const MaterialPoint& mp, const PointDistribution::Laws& laws) {
  return laws[mp.law]->point_sharing() != nullptr;
}

}  // namespace

void PointDistribution::set_ranks(std::shared_ptr<const Ranks> ranks, const Laws& laws) {
  if (ranks->size() > 1)
    for (const auto& law : laws)
      if (!law->replicable() && !law->point_sharing())
        throw std::invalid_argument("law \"" + law->name() + "\" cannot run on " + std::to_string(ranks->size()) +
                                    " MPI ranks (it is neither replicated nor spread over ranks): run this scene "
                                    "without mpirun, on the threads of one process");
  ranks_ = std::move(ranks);
}

long PointDistribution::share_updates(std::vector<MaterialPoint>& points, const Laws& laws,
                                      const std::vector<char>& skipped) const {
  common::ByteWriter mine;
  for (std::size_t p = 0; p < points.size(); ++p) {
    const MaterialPoint& mp = points[p];
    if (!spread_point(mp, laws) || !updates_here(mp, laws)) continue;
    mine.put(mp.id);
    mine.put_matrix(mp.stress.in_plane);
    mine.put(mp.stress.zz);
    mine.put(mp.volume);
    mine.put_matrix(mp.pending_increment);
    mine.put(mp.pending_time);
    mine.put(skipped[p]);
    laws[mp.law]->point_sharing()->write_summary(mp.slot, mine);
  }
  const std::vector<std::vector<char>> all = ranks_->all_gather(mine.bytes());
  for (const std::vector<char>& message : all) shared_update_bytes_ += static_cast<double>(message.size());
  const std::vector<std::uint32_t> index = index_of_ids(points);
  long skipped_elsewhere = 0;
  for (int r = 0; r < ranks_->size(); ++r) {
    if (r == ranks_->rank()) continue;
    common::ByteReader in(all[r]);
    while (!in.at_end()) {
      MaterialPoint& mp = points.at(index.at(in.get<std::uint32_t>()));
      mp.stress.in_plane = in.get_matrix<Mat2>();
      mp.stress.zz = in.get<double>();
      mp.volume = in.get<double>();
      mp.pending_increment = in.get_matrix<Mat2>();
      mp.pending_time = in.get<double>();
      skipped_elsewhere += in.get<char>();
      laws[mp.law]->point_sharing()->read_summary(mp.slot, in);
    }
  }
  return skipped_elsewhere;
}

void PointDistribution::share_point_states(const std::vector<MaterialPoint>& points, const Laws& laws,
                                           const std::vector<std::uint32_t>& ids) const {
  if (!spread()) return;
  const auto wanted = [&](const MaterialPoint& mp) {
    return spread_point(mp, laws) && (ids.empty() || std::find(ids.begin(), ids.end(), mp.id) != ids.end());
  };
  common::ByteWriter mine;
  for (const MaterialPoint& mp : points) {
    if (!wanted(mp) || !updates_here(mp, laws)) continue;
    mine.put(mp.id);
    laws[mp.law]->point_sharing()->write_point_state(mp.slot, mine);
  }
  const std::vector<std::vector<char>> all = ranks_->all_gather(mine.bytes());
  const std::vector<std::uint32_t> index = index_of_ids(points);
  for (int r = 0; r < ranks_->size(); ++r) {
    if (r == ranks_->rank()) continue;
    common::ByteReader in(all[r]);
    while (!in.at_end()) {
      const MaterialPoint& mp = points.at(index.at(in.get<std::uint32_t>()));
      laws[mp.law]->point_sharing()->read_point_state(mp.slot, in);
    }
  }
}

std::pair<double, std::uint32_t> PointDistribution::min_over_ranks(std::pair<double, std::uint32_t> mine) const {
  if (!spread()) return mine;
  common::ByteWriter out;
  out.put(mine.first), out.put(mine.second);
  std::pair<double, std::uint32_t> best{std::numeric_limits<double>::infinity(), UINT32_MAX};
  for (const std::vector<char>& bytes : ranks_->all_gather(out.bytes())) {
    common::ByteReader in(bytes);
    const double value = in.get<double>();
    const auto id = in.get<std::uint32_t>();
    if (value < best.first || (value == best.first && id < best.second)) best = {value, id};
  }
  return best;
}

}  // namespace grainbank::mpm
