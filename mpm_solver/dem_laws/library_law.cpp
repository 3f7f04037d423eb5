#include "mpm_solver/dem_laws/library_law.hpp"

#include <chrono>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <string>

#include "database/lookup/state_key.hpp"
#include "dem_sampler/cell/cell_state_bytes.hpp"

namespace grainbank::mpm {

LibraryLaw::LibraryLaw(std::unique_ptr<LibraryLink> link, LibraryLawSettings settings)
    : link_(std::move(link)),
      settings_(settings),
      model_(link_->template_cell(), settings.live),
      template_measures_(link_->template_cell().measures()) {
  if (settings_.lookup.k == 0) throw std::invalid_argument("lookup.k: expected an integer >= 1");
  if (!(settings_.lookup.tolerance >= 0)) throw std::invalid_argument("lookup.tolerance: expected a number >= 0");
  if (!(settings_.max_drive_strain > 0)) throw std::invalid_argument("max_drive_strain: expected a positive number");
  if (settings_.return_after < 0) throw std::invalid_argument("return_after: expected an integer >= 0");
  if (settings_.fallback == Fallback::none && link_->index().size() == 0)
    throw std::invalid_argument("the cache law needs a library with records (it has none; use hybrid or sample paths)");
  // Only a law that runs live cells has responses to give back.
  if (settings_.enrich && settings_.fallback != Fallback::none) {
    long budget = settings_.snapshot_budget;
    if (budget != Enrichment::kUnlimited)
      budget = budget / settings_.ranks + (settings_.rank < budget % settings_.ranks ? 1 : 0);
    enrichment_ = std::make_unique<Enrichment>(*link_, settings_.snapshot_interval, budget, settings_.rank == 0);
  }
}

LibraryLaw::~LibraryLaw() {
  // finish() is the normal way out; this only keeps the responses of a run that ended otherwise.
  try {
    finish();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "warning: live responses of this run not written to the library: %s\n", e.what());
  }
}

std::size_t LibraryLaw::add_point(PointStress& initial_stress) {
  // Points start in the template's state, which the library answers exactly by construction.
  Point p;
  p.damage = template_measures_.damage;
  p.modulus = model_.modulus(template_measures_);
  points_.push_back(std::move(p));
  initial_stress = plane_stress_of(template_measures_.stress);
  return points_.size() - 1;
}

namespace {

// The total-strain key needs the polar decomposition of F. A lone point at a front can be sheared
// until det F is round-off of either sign (|F| ~ 1e8, stop 73): no library path reaches it, and a
// warm start has no deformation to drive a cell to. Only a cell rebuilt from the point's increments
// answers it.
bool keyable(const Mat2& F) { return lookup::has_polar_decomposition(embed_plane_strain(F)); }

std::string unkeyable(const Mat2& F, bool warm_start) {
  std::ostringstream msg;
  msg << "its deformation gradient F = [[" << F(0, 0) << ", " << F(0, 1) << "], [" << F(1, 0) << ", " << F(1, 1)
      << "]] has det F = " << F.determinant()
      << ": sheared until det F is round-off, it has no total strain the library's key can place"
      << (warm_start ? " and no deformation a warm start can drive a cell to" : "")
      << "; use the hybrid law with fallback.start \"replay\", which rebuilds the point's cell from its increments, "
         "or the surrogate law, which keys a point by its state";
  return msg.str();
}

}  // namespace

lookup::LookupAnswer LibraryLaw::ask(const Point& p, const Mat2& F, const Mat2& L) const {
  lookup::LookupState state;
  state.F = embed_plane_strain(F);
  state.L.topLeftCorner<2, 2>() = L;
  state.damage = p.damage;
  return link_->index().query(state, settings_.lookup);
}

void LibraryLaw::update(std::size_t slot, const KinematicIncrement& increment, const Mat2& F, PointStress& stress) {
  Point& p = points_[slot];
  if (settings_.fallback == Fallback::replay) p.history.push_back(increment);

  if (p.cell) {
    advance_live(p, increment, stress);
    if (settings_.return_after > 0 && keyable(F)) {
      const lookup::LookupAnswer answer = ask(p, F, increment.L);
      p.steps_inside = answer.hit ? p.steps_inside + 1 : 0;
      if (p.steps_inside >= settings_.return_after) {
        if (p.path.open()) enrichment_->finish(p.path);
        p.cell.reset();
        --live_points_;
        p.steps_inside = 0;
        ++p.counters.returned_to_cache;
      }
    }
    return;
  }

  const bool placed = keyable(F);
  if (!placed && settings_.fallback != Fallback::replay) throw std::runtime_error(unkeyable(F, settings_.fallback == Fallback::warm_start));
  const lookup::LookupAnswer answer = placed ? ask(p, F, increment.L) : lookup::LookupAnswer{};
  if (!answer.hit && settings_.fallback != Fallback::none) {
    ++p.counters.misses;
    go_live(slot, p, increment.F.inverse() * F, answer, increment.dt);
    advance_live(p, increment, stress);
    return;
  }
  ++(answer.hit ? p.counters.hits : p.counters.misses);
  p.counters.estimated_error_sum += answer.estimated_error;
  stress = plane_stress_of(answer.stress);
  p.source = answer.hit ? StressSource::hit : StressSource::miss;
  p.error = answer.estimated_error;
  if (answer.neighbours > 0) {
    p.damage = answer.damage;
    dem::CellMeasures m;
    m.solid_fraction = answer.solid_fraction;
    m.coordination = answer.coordination;
    p.modulus = model_.modulus(m);
  }
}

void LibraryLaw::go_live(std::size_t slot, Point& p, const Mat2& F_before, const lookup::LookupAnswer& answer,
                         double dt) {
  const auto start = std::chrono::steady_clock::now();
  nlohmann::json origin = {{"mpm_point_slot", slot}};
  std::optional<db::StoredCell> snapshot;
  if (settings_.fallback == Fallback::warm_start && answer.neighbours > 0) snapshot = link_->snapshot_before(answer.nearest);
  p.cell = std::make_unique<dem::DemCell>(snapshot ? model_.cell_from(std::move(snapshot->state)) : model_.new_cell());
  long increments = 0;
  if (settings_.fallback == Fallback::replay) {
    // The history already holds this step's increment, which advance_live applies.
    const std::vector<KinematicIncrement> before(p.history.begin(), p.history.end() - 1);
    increments = replay(*p.cell, before, model_, p.counters);
    origin["start"] = "replay";
  } else {
    const std::size_t spheres = p.cell->size();
    increments = drive_to(*p.cell, embed_plane_strain(F_before), settings_.max_drive_strain, dt,
                          settings_.live.substepping);
    LiveCellModel::count_retilings(spheres, *p.cell, p.counters);
    origin["start"] = snapshot ? nlohmann::json{{"path", answer.nearest.path_id}, {"record", answer.nearest.record_index}}
                               : nlohmann::json("template");
  }
  p.steps_inside = 0;
  ++live_points_;
  ++p.counters.went_live;
  p.counters.warm_start_increments += static_cast<std::uint64_t>(increments);
  if (enrichment_) start_enriched_path(p, origin);
  p.counters.warm_start_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void LibraryLaw::start_enriched_path(Point& p, const nlohmann::json& origin) {
  p.path = enrichment_->start(origin);
  ++p.counters.enriched_paths;
}

void LibraryLaw::advance_live(Point& p, const KinematicIncrement& increment, PointStress& stress) {
  const dem::Mat3 sigma = model_.advance(*p.cell, increment, p.counters);
  stress = plane_stress_of(sigma);
  const dem::CellMeasures m = p.cell->measures();
  p.modulus = model_.modulus(m);
  p.damage = m.damage;
  p.source = StressSource::live;
  p.error = 0;
  ++p.counters.live_updates;
  if (enrichment_ && !p.path.open()) start_enriched_path(p, {{"start", "restart"}});
  if (p.path.open()) {
    dem::Mat3 L = dem::Mat3::Zero();
    L.topLeftCorner<2, 2>() = increment.L;
    enrichment_->add(p.path, *p.cell, L, sigma);
    ++p.counters.enriched_records;
  }
}

namespace {

// Per point of the law: slot, damage, live (0/1), steps inside the tolerance; live cells as
// "cell_<slot>"; the replay histories as append_history writes them.
constexpr std::size_t kPointColumns = 4;
std::string cell_name(std::size_t slot) { return "cell_" + std::to_string(slot); }

}  // namespace

void LibraryLaw::save_state(LawStateWriter& out) const {
  std::vector<double> rows, history;
  for (std::size_t slot = 0; slot < points_.size(); ++slot) {
    const Point& p = points_[slot];
    rows.insert(rows.end(), {double(slot), p.damage, p.cell ? 1.0 : 0.0, double(p.steps_inside)});
    append_history(history, slot, p.history);
    if (p.cell) out.write_cell(cell_name(slot), *p.cell);
  }
  out.write_table("library_points", rows, kPointColumns);
  out.write_table("replay_history", history, kHistoryColumns);
}

void LibraryLaw::restore_state(LawStateReader& in) {
  for (Point& p : points_) p.history.clear();
  const std::vector<double> history = in.read_table("replay_history", kHistoryColumns);
  for (const auto& [slot, increment] : history_rows(history)) points_.at(slot).history.push_back(increment);
  const std::vector<double> rows = in.read_table("library_points", kPointColumns);
  for (std::size_t r = 0; r < rows.size(); r += kPointColumns) {
    const auto slot = static_cast<std::size_t>(rows[r]);
    Point& p = points_.at(slot);
    p.damage = rows[r + 1];
    p.steps_inside = static_cast<int>(rows[r + 3]);
    if (p.cell) --live_points_;
    p.cell.reset();
    if (rows[r + 2] == 0) continue;
    p.cell = std::make_unique<dem::DemCell>(model_.cell_from(in.read_cell(cell_name(slot))));
    ++live_points_;
    p.modulus = model_.modulus(p.cell->measures());
    p.source = StressSource::live;
  }
}

void LibraryLaw::write_summary(std::size_t slot, common::ByteWriter& out) const {
  const Point& p = points_[slot];
  out.put(p.damage), out.put(p.modulus), out.put(p.error), out.put(p.source), out.put(p.counters);
}

void LibraryLaw::read_summary(std::size_t slot, common::ByteReader& in) {
  Point& p = points_[slot];
  p.damage = in.get<double>(), p.modulus = in.get<double>(), p.error = in.get<double>();
  p.source = in.get<StressSource>();
  p.counters = in.get<CouplingCounters>();
}

void LibraryLaw::write_point_state(std::size_t slot, common::ByteWriter& out) const {
  const Point& p = points_[slot];
  write_summary(slot, out);
  out.put(p.steps_inside);
  out.put<std::uint64_t>(p.history.size());
  for (const KinematicIncrement& increment : p.history) {
    out.put_matrix(increment.F), out.put_matrix(increment.L);
    out.put(increment.dt);
  }
  out.put(p.cell != nullptr);
  if (p.cell) dem::write_cell_state(p.cell->state(), out);
}

void LibraryLaw::read_point_state(std::size_t slot, common::ByteReader& in) {
  read_summary(slot, in);
  Point& p = points_[slot];
  p.steps_inside = in.get<int>();
  p.history = in.get_each([&] {
    KinematicIncrement increment;
    increment.F = in.get_matrix<Mat2>(), increment.L = in.get_matrix<Mat2>();
    increment.dt = in.get<double>();
    return increment;
  });
  if (p.cell) --live_points_;
  p.cell.reset();
  if (in.get<bool>()) {
    p.cell = std::make_unique<dem::DemCell>(model_.cell_from(dem::read_cell_state(in)));
    ++live_points_;
  }
}

void LibraryLaw::release(std::size_t slot) {
  Point& p = points_[slot];
  if (p.path.open()) enrichment_->finish(p.path);
}

double LibraryLaw::volume_ratio(std::size_t slot, double kinematic) const {
  const Point& p = points_[slot];
  return p.cell ? model_.volume_ratio(*p.cell) : kinematic;
}

double LibraryLaw::time_step_limit(std::size_t slot, const Mat2& F, const Mat2& L) const {
  const Point& p = points_[slot];
  return p.cell ? model_.time_step_limit(*p.cell, L) : model_.time_step_limit(F, L);
}

CouplingCounters LibraryLaw::counters() const {
  CouplingCounters total;
  for (const Point& p : points_) total += p.counters;
  return total;
}

void LibraryLaw::finish() {
  for (Point& p : points_)
    if (p.path.open()) enrichment_->finish(p.path);
}

}  // namespace grainbank::mpm
