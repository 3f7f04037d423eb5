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

template <class Send, class Receive>
void PointDistribution::move_point_states(const std::vector<MaterialPoint>& points, const Laws& laws, Send&& send,
                                          Receive&& receive, bool to_root_only) const {
  common::ByteWriter mine;
  for (const MaterialPoint& mp : points) {
    if (!spread_point(mp, laws) || !send(mp)) continue;
    common::ByteWriter state;
    laws[mp.law]->point_sharing()->write_point_state(mp.slot, state);
    mine.put(mp.id);
    mine.put_vector(state.bytes());
  }
  const std::vector<std::vector<char>> all =
      to_root_only ? ranks_->gather_to_root(mine.bytes()) : ranks_->all_gather(mine.bytes());
  const std::vector<std::uint32_t> index = index_of_ids(points);
  for (int r = 0; r < static_cast<int>(all.size()); ++r) {
    if (r == ranks_->rank()) continue;
    common::ByteReader in(all[r]);
    while (!in.at_end()) {
      const MaterialPoint& mp = points.at(index.at(in.get<std::uint32_t>()));
      common::ByteReader state = in.take(in.get<std::uint64_t>());
      if (receive(mp)) laws[mp.law]->point_sharing()->read_point_state(mp.slot, state);
    }
  }
}

void PointDistribution::gather_point_states(const std::vector<MaterialPoint>& points, const Laws& laws,
                                            const std::vector<std::uint32_t>& ids) const {
  if (!spread()) return;
  const auto wanted = [&](const MaterialPoint& mp) {
    return ids.empty() || std::find(ids.begin(), ids.end(), mp.id) != ids.end();
  };
  move_point_states(
      points, laws, [&](const MaterialPoint& mp) { return wanted(mp) && updates_here(mp, laws); }, wanted, true);
}

std::size_t PointDistribution::rebalance(const std::vector<MaterialPoint>& points, const Laws& laws,
                                         const std::vector<double>& seconds) {
  if (!spread()) return 0;
  // Each point's cost is known on its owner only.
  const std::vector<double> cost = sum_over_ranks(*ranks_, seconds);
  std::vector<std::uint32_t> order;
  for (const MaterialPoint& mp : points)
    if (spread_point(mp, laws)) order.push_back(mp.id);
  std::sort(order.begin(), order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return cost[a] > cost[b] || (cost[a] == cost[b] && a < b); });
  // The best deal greedy placement finds: the costliest first, onto the least-loaded rank.
  const auto ranks = static_cast<std::size_t>(ranks_->size());
  const auto least_loaded = [](const std::vector<double>& load) {
    return static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
  };
  std::vector<double> greedy(ranks, 0.0), now(ranks, 0.0);
  for (std::uint32_t id : order) {
    greedy[least_loaded(greedy)] += cost[id];
    now[static_cast<std::size_t>(owner(id))] += cost[id];
  }
  // Moving costs a state transfer (a whole cell), and a hybrid point's enriched path ends at each
  // move: the points stay where they are unless the busiest rank is over kLoadTolerance above the
  // greedy deal's, and then each stays while its rank remains within that margin.
  const double cap = *std::max_element(greedy.begin(), greedy.end()) * (1 + kLoadTolerance);
  if (*std::max_element(now.begin(), now.end()) <= cap) return 0;
  std::vector<int> dealt(points.size(), 0);
  for (std::uint32_t id = 0; id < dealt.size(); ++id) dealt[id] = owner(id);
  std::vector<double> load(ranks, 0.0);
  for (std::uint32_t id : order) {
    auto rank = static_cast<std::size_t>(owner(id));
    if (load[rank] + cost[id] > cap) rank = least_loaded(load);
    dealt[id] = static_cast<int>(rank);
    load[rank] += cost[id];
  }
  std::size_t moved = 0;
  for (std::uint32_t id : order) moved += dealt[id] != owner(id);
  const auto leaves = [&](const MaterialPoint& mp) { return dealt[mp.id] != owner(mp.id) && updates_here(mp, laws); };
  move_point_states(
      points, laws, leaves,
      [&](const MaterialPoint& mp) { return dealt[mp.id] != owner(mp.id) && dealt[mp.id] == ranks_->rank(); }, false);
  for (const MaterialPoint& mp : points)
    if (spread_point(mp, laws) && leaves(mp)) laws[mp.law]->point_sharing()->release(mp.slot);
  owner_ = std::move(dealt);
  moved_points_ += moved;
  return moved;
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
