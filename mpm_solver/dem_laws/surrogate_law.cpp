#include "mpm_solver/dem_laws/surrogate_law.hpp"

#include <algorithm>
#include <chrono>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>

#include "dem_sampler/driver/cell_input.hpp"
#include "mpm_solver/dem_laws/dem_material_input.hpp"
#include "mpm_solver/dem_laws/library_link.hpp"
#include "mpm_solver/dem_laws/warm_start.hpp"
#include "mpm_solver/laws/law_registry.hpp"
#include "database/store/error.hpp"
#include "database/surrogate/length_scales.hpp"
#include "database/surrogate/surrogate_step.hpp"

namespace grainbank::mpm {

namespace {

surrogate::LengthScales fitted_scales(const surrogate::Dataset& dataset, const surrogate::SurrogateOptions& options) {
  // Fewer than two samples tell nothing of their spread: unit scales.
  if (dataset.samples.size() < 2) return surrogate::initial_length_scales(dataset.samples);
  return surrogate::fit_length_scales(dataset.constants, dataset.samples, options).scales;
}

dem::Mat3 embed_velocity_gradient(const Mat2& L) {
  dem::Mat3 out = dem::Mat3::Zero();
  out.topLeftCorner<2, 2>() = L;
  return out;
}

surrogate::PointState state_of(const dem::Mat3& stress, const dem::CellMeasures& m) {
  return {stress, m.solid_fraction, m.coordination, m.damage};
}

}  // namespace

SurrogateLaw::SurrogateLaw(const dem::DemCell& cell_template, surrogate::Dataset dataset,
                           SurrogateLawSettings settings, std::vector<StateSnapshot> snapshots)
    : settings_(settings), model_(cell_template, settings.live) {
  if (!(settings_.tolerance >= 0)) throw std::invalid_argument("tolerance: expected a number >= 0 [Pa]");
  if (settings_.return_after < 0) throw std::invalid_argument("return_after: expected an integer >= 0");
  if (!(settings_.error_budget > 0)) throw std::invalid_argument("error_budget: expected a positive number [Pa]");
  if (settings_.sample_span < 1) throw std::invalid_argument("sample_span: expected an integer >= 1");
  const dem::CellMeasures m = cell_template.measures();
  template_state_ = state_of(m.stress, m);
  index_ = std::make_unique<surrogate::SurrogateIndex>(dataset.constants, fitted_scales(dataset, settings_.surrogate),
                                                       settings_.surrogate);
  index_->insert(dataset.samples);
  StateWarmStartSettings& warm = settings_.state_warm_start;
  if (warm.stress_tolerance == 0) warm.stress_tolerance = settings_.tolerance;
  if (settings_.warm_start == SurrogateLawSettings::WarmStart::state && warm.stress_tolerance > 0) {
    snapshots.push_back({template_state_, cell_template.state()});
    warm_start_.emplace(std::move(snapshots), index_->constants(), index_->scales(), warm);
  }
}

std::size_t SurrogateLaw::add_point(PointStress& initial_stress) {
  Point p;
  p.state = template_state_;
  points_.push_back(std::move(p));
  initial_stress = plane_stress_of(template_state_.stress);
  return points_.size() - 1;
}

void SurrogateLaw::update(std::size_t slot, const KinematicIncrement& increment, const Mat2&, PointStress& stress) {
  Point& p = points_[slot];
  p.history.push_back(increment);
  const dem::Mat3 L = embed_velocity_gradient(increment.L);

  if (p.cell) {
    // Asked before this step's response is learned: would the surrogate have answered it?
    const bool inside =
        settings_.return_after > 0 &&
        surrogate::surrogate_step(*index_, p.state, L, increment.dt, settings_.tolerance).hit;
    advance_live(slot, p, increment, L, stress);
    p.steps_inside = inside ? p.steps_inside + 1 : 0;
    // A spell the budget started needs no hysteresis: the surrogate could answer the point, it
    // went live to end a drift, and one step within the tolerance shows the drift is ended.
    const int steps_to_return = p.budget_spell ? 1 : settings_.return_after;
    if (settings_.return_after > 0 && p.steps_inside >= steps_to_return) {
      // The point keeps the cell's state.
      park(p, p.history.size());
      --live_points_;
      p.steps_inside = 0;
      ++p.counters.returned_to_cache;
    }
    return;
  }

  surrogate::SurrogateStep step = surrogate::surrogate_step(*index_, p.state, L, increment.dt, settings_.tolerance);
  const bool budget_spent = step.hit && p.spent + step.estimated_error > settings_.error_budget;
  if (budget_spent && warm_start_) {
    reanchor(p);
    step = surrogate::surrogate_step(*index_, p.state, L, increment.dt, settings_.tolerance);
  }
  const bool spell_on_budget = budget_spent && !warm_start_;
  if (!step.hit || spell_on_budget) {
    ++p.counters.misses;
    if (spell_on_budget) ++p.counters.went_live_on_budget;
    p.budget_spell = spell_on_budget;
    go_live(p);
    advance_live(slot, p, increment, L, stress);
    return;
  }
  ++p.counters.hits;
  p.counters.estimated_error_sum += step.estimated_error;
  p.spent += step.estimated_error;
  p.state = step.state;
  stress = plane_stress_of(p.state.stress);
  p.source = StressSource::hit;
  p.error = step.estimated_error;
}

bool SurrogateLaw::start_cell(Point& p) {
  const auto start = std::chrono::steady_clock::now();
  // The history already holds this step's increment, which advance_live applies.
  const auto before_this_step = p.history.end() - 1;
  p.cell_is_exact = false;
  bool caught_up = false;
  if (warm_start_ && p.history.size() > 1) {
    const auto motion_since = [&](std::size_t seen) {
      return std::span<const KinematicIncrement>(p.history.data() + seen, p.history.size() - 1 - seen);
    };
    std::optional<OwnCell> own;
    if (p.parked)
      own.emplace(OwnCell{std::move(*p.parked), motion_since(p.parked_at)});
    else if (settings_.state_warm_start.first_cell == StateWarmStartSettings::FirstCell::template_caught_up)
      own.emplace(OwnCell{model_.new_cell(), motion_since(0)});  // every point starts in the template's state
    p.parked.reset();
    WarmStartOutcome outcome = warm_start_->start(p.state, model_, std::move(own));
    caught_up = outcome.own;
    p.counters += outcome.catch_up;
    p.counters.warm_start_servo_steps += static_cast<std::uint64_t>(outcome.servo.steps);
    const bool servo_failed = !outcome.own && !outcome.servo.converged;
    if (servo_failed) ++p.counters.servo_unconverged;
    if (!servo_failed || !settings_.state_warm_start.replay_unconverged)
      p.cell = std::make_unique<dem::DemCell>(std::move(outcome.cell));
  }
  if (!p.cell) {
    const auto from = p.history.begin() + static_cast<std::ptrdiff_t>(p.checkpoint ? p.checkpoint_at : 0);
    p.cell = p.checkpoint ? std::move(p.checkpoint) : std::make_unique<dem::DemCell>(model_.new_cell());
    p.counters.warm_start_increments +=
        static_cast<std::uint64_t>(replay(*p.cell, {from, before_this_step}, model_, p.counters));
    p.cell_is_exact = true;
  }
  p.spent = 0;
  p.span.clear();
  const dem::CellMeasures m = p.cell->measures();
  p.state = state_of(m.stress, m);  // the cell's state, not the surrogate's estimate of it
  p.counters.warm_start_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return caught_up;
}

void SurrogateLaw::go_live(Point& p) {
  start_cell(p);
  p.steps_inside = 0;
  ++live_points_;
  ++p.counters.went_live;
}

void SurrogateLaw::reanchor(Point& p) {
  const double damage = p.state.damage;
  // Bonds do not heal: a servoed snapshot has no more broken bonds than the point, and taking its D
  // would drop the damage the point has integrated (stop 46: the a = 1 column kept its mean D at
  // 0.02 against live's 0.24, and stood). The point's own cell, caught up on its motion, broke the
  // bonds that motion breaks: its D is the better estimate, and the point takes it.
  if (!start_cell(p)) p.state.damage = std::max(p.state.damage, damage);
  // The cell has not seen this step's increment: the surrogate answers it from the cell's state.
  park(p, p.history.size() - 1);
  ++p.counters.reanchored;
}

void SurrogateLaw::park(Point& p, std::size_t seen) {
  if (p.cell_is_exact) {
    p.checkpoint = std::make_unique<dem::DemCell>(*p.cell);
    p.checkpoint_at = seen;
  }
  if (warm_start_) {
    p.parked = std::move(p.cell);
    p.parked_at = seen;
  }
  p.cell.reset();
}

void SurrogateLaw::advance_live(std::size_t slot, Point& p, const KinematicIncrement& increment, const dem::Mat3& L,
                                PointStress& stress) {
  const surrogate::PointState before = p.state;
  const dem::Mat3 sigma = model_.advance(*p.cell, increment, p.counters);
  p.state = state_of(sigma, p.cell->measures());
  stress = plane_stress_of(sigma);
  p.source = StressSource::live;
  p.error = 0;
  ++p.counters.live_updates;
  p.span.push_back({before, L, increment.dt});
  if (p.span.size() > settings_.sample_span) p.span.erase(p.span.begin());
  learn_span(slot, p);
}

void SurrogateLaw::learn_span(std::size_t slot, Point& p) {
  dem::Mat3 L_dt = dem::Mat3::Zero();
  double duration = 0;
  for (const Point::SpanStep& s : p.span) {
    L_dt += s.L * s.dt;
    duration += s.dt;
  }
  // A rest or a pure spin has no rate per |D| (rate_answer.hpp): nothing to learn.
  if (duration <= 0) return;
  // One step is learned under its own L, not (L dt)/dt, which may differ in the last bit.
  const dem::Mat3 mean_L = p.span.size() == 1 ? p.span.front().L : dem::Mat3(L_dt / duration);
  if ((mean_L + mean_L.transpose()).norm() > 0)
    p.learned_this_step.push_back(surrogate::make_sample(
        p.span.front().before, p.state, mean_L, duration, index_->constants(),
        {-static_cast<std::int64_t>(slot) - 1, static_cast<std::int64_t>(p.history.size()) - 1}));
}

void SurrogateLaw::end_step() {
  std::vector<surrogate::Sample> samples;
  for (Point& p : points_) {
    samples.insert(samples.end(), p.learned_this_step.begin(), p.learned_this_step.end());
    p.learned_this_step.clear();
  }
  if (!samples.empty()) learn(samples);
}

void SurrogateLaw::learn(const std::vector<surrogate::Sample>& samples) {
  index_->insert(samples);
  learned_.insert(learned_.end(), samples.begin(), samples.end());
}

std::size_t SurrogateLaw::learned() const { return learned_.size(); }

double SurrogateLaw::p_wave_modulus(std::size_t slot) const {
  dem::CellMeasures m;
  m.solid_fraction = points_[slot].state.solid_fraction;
  m.coordination = points_[slot].state.coordination;
  return model_.modulus(m);
}

double SurrogateLaw::time_step_limit(std::size_t slot, const Mat2& F, const Mat2& L) const {
  const Point& p = points_[slot];
  return p.cell ? model_.time_step_limit(*p.cell, L) : model_.time_step_limit(F, L);
}

namespace {

// Per point: slot, σ (9, row-major), φ, Z, D, live (0/1), steps inside the tolerance, error spent
// since its last live spell [Pa], live cell started by replay (0/1), live spell started by the
// budget (0/1); live cells as "cell_<slot>"; the replay histories as append_history writes them;
// the learned samples as rows features, answer, origin path, origin record, in insertion order;
// per kept cell: slot and the increments it has seen, the cell as "parked_<slot>"; per
// checkpoint: slot and the increments it has seen, the cell as "checkpoint_<slot>"; per step of a live
// cell's sample span, in order: slot, the state before it (σ, φ, Z, D), L (9, row-major), dt.
constexpr std::size_t kStateColumns = 12;
constexpr std::size_t kPointColumns = 1 + kStateColumns + 5;
constexpr std::size_t kSampleColumns = surrogate::kFeatureCount + surrogate::kAnswerSize + 2;
constexpr std::size_t kParkedColumns = 2;
constexpr std::size_t kCheckpointColumns = 2;
constexpr std::size_t kSpanColumns = 1 + kStateColumns + 9 + 1;
std::string cell_name(std::size_t slot) { return "cell_" + std::to_string(slot); }
std::string parked_cell_name(std::size_t slot) { return "parked_" + std::to_string(slot); }
std::string checkpoint_cell_name(std::size_t slot) { return "checkpoint_" + std::to_string(slot); }

void append_state(std::vector<double>& rows, const surrogate::PointState& state) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) rows.push_back(state.stress(i, j));
  rows.insert(rows.end(), {state.solid_fraction, state.coordination, state.damage});
}

surrogate::PointState state_from(const double* row) {
  surrogate::PointState state;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) state.stress(i, j) = row[3 * i + j];
  state.solid_fraction = row[9];
  state.coordination = row[10];
  state.damage = row[11];
  return state;
}

}  // namespace

void SurrogateLaw::save_state(LawStateWriter& out) const {
  std::vector<double> rows, history, samples, parked, checkpoints, span;
  for (std::size_t slot = 0; slot < points_.size(); ++slot) {
    const Point& p = points_[slot];
    rows.push_back(double(slot));
    append_state(rows, p.state);
    rows.insert(rows.end(), {p.cell ? 1.0 : 0.0, double(p.steps_inside), p.spent, p.cell_is_exact ? 1.0 : 0.0,
                             p.budget_spell ? 1.0 : 0.0});
    append_history(history, slot, p.history);
    if (p.cell) out.write_cell(cell_name(slot), *p.cell);
    if (p.parked) {
      parked.insert(parked.end(), {double(slot), double(p.parked_at)});
      out.write_cell(parked_cell_name(slot), *p.parked);
    }
    if (p.checkpoint) {
      checkpoints.insert(checkpoints.end(), {double(slot), double(p.checkpoint_at)});
      out.write_cell(checkpoint_cell_name(slot), *p.checkpoint);
    }
    for (const Point::SpanStep& step : p.span) {
      span.push_back(double(slot));
      append_state(span, step.before);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) span.push_back(step.L(i, j));
      span.push_back(step.dt);
    }
  }
  for (const surrogate::Sample& s : learned_) {
    samples.insert(samples.end(), s.features.begin(), s.features.end());
    samples.insert(samples.end(), s.answer.begin(), s.answer.end());
    samples.insert(samples.end(), {double(s.origin.path_id), double(s.origin.record_index)});
  }
  out.write_table("surrogate_points", rows, kPointColumns);
  out.write_table("replay_history", history, kHistoryColumns);
  out.write_table("surrogate_learned", samples, kSampleColumns);
  out.write_table("surrogate_parked", parked, kParkedColumns);
  out.write_table("surrogate_checkpoints", checkpoints, kCheckpointColumns);
  out.write_table("surrogate_span", span, kSpanColumns);
}

void SurrogateLaw::restore_state(LawStateReader& in) {
  if (learned() > 0) throw std::logic_error("surrogate law: restore_state into a law that has already learned samples");
  for (Point& p : points_) p.history.clear();
  const std::vector<double> history = in.read_table("replay_history", kHistoryColumns);
  for (const auto& [slot, increment] : history_rows(history)) points_.at(slot).history.push_back(increment);
  const std::vector<double> rows = in.read_table("surrogate_points", kPointColumns);
  for (std::size_t r = 0; r < rows.size(); r += kPointColumns) {
    const auto slot = static_cast<std::size_t>(rows[r]);
    Point& p = points_.at(slot);
    p.state = state_from(&rows[r + 1]);
    p.steps_inside = static_cast<int>(rows[r + 14]);
    p.spent = rows[r + 15];
    p.cell_is_exact = rows[r + 16] != 0;
    p.budget_spell = rows[r + 17] != 0;
    p.error = 0;
    p.source = StressSource::hit;
    if (p.cell) --live_points_;
    p.cell.reset();
    if (rows[r + 13] == 0) continue;
    p.cell = std::make_unique<dem::DemCell>(model_.cell_from(in.read_cell(cell_name(slot))));
    ++live_points_;
    p.source = StressSource::live;
  }
  for (Point& p : points_) p.parked.reset();
  const std::vector<double> parked = in.read_table("surrogate_parked", kParkedColumns);
  for (std::size_t r = 0; r < parked.size(); r += kParkedColumns) {
    const auto slot = static_cast<std::size_t>(parked[r]);
    Point& p = points_.at(slot);
    p.parked_at = static_cast<std::size_t>(parked[r + 1]);
    p.parked = std::make_unique<dem::DemCell>(model_.cell_from(in.read_cell(parked_cell_name(slot))));
  }
  for (Point& p : points_) p.checkpoint.reset();
  const std::vector<double> checkpoints = in.read_table("surrogate_checkpoints", kCheckpointColumns);
  for (std::size_t r = 0; r < checkpoints.size(); r += kCheckpointColumns) {
    const auto slot = static_cast<std::size_t>(checkpoints[r]);
    Point& p = points_.at(slot);
    p.checkpoint_at = static_cast<std::size_t>(checkpoints[r + 1]);
    p.checkpoint = std::make_unique<dem::DemCell>(model_.cell_from(in.read_cell(checkpoint_cell_name(slot))));
  }
  for (Point& p : points_) p.span.clear();
  // A restart file written before samples had spans has none: its samples spanned one step.
  const std::vector<double> span =
      in.has_table("surrogate_span") ? in.read_table("surrogate_span", kSpanColumns) : std::vector<double>{};
  for (std::size_t r = 0; r < span.size(); r += kSpanColumns) {
    Point::SpanStep step;
    step.before = state_from(&span[r + 1]);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) step.L(i, j) = span[r + 1 + kStateColumns + 3 * i + j];
    step.dt = span[r + kSpanColumns - 1];
    points_.at(static_cast<std::size_t>(span[r])).span.push_back(step);
  }
  const std::vector<double> table = in.read_table("surrogate_learned", kSampleColumns);
  std::vector<surrogate::Sample> samples;
  for (std::size_t r = 0; r < table.size(); r += kSampleColumns) {
    surrogate::Sample s;
    std::copy_n(table.begin() + static_cast<std::ptrdiff_t>(r), surrogate::kFeatureCount, s.features.begin());
    std::copy_n(table.begin() + static_cast<std::ptrdiff_t>(r + surrogate::kFeatureCount), surrogate::kAnswerSize,
                s.answer.begin());
    s.origin = {static_cast<std::int64_t>(table[r + kSampleColumns - 2]),
                static_cast<std::int64_t>(table[r + kSampleColumns - 1])};
    samples.push_back(s);
  }
  if (!samples.empty()) learn(samples);
}

namespace {

using common::JsonNode;
using common::Range;

// {"law": "surrogate", "library": LIB, "template": id, "tolerance": Pa} with the optional "cell"
// (the library must have its material), "error_budget" [Pa], "k", "sample_span", "fallback":
// {"return_after", "warm_start": "state" | "replay", "stress_tolerance" [Pa, default: tolerance],
// "max_servo_steps", "servo_inertial_number", "catch_up_steps", "catch_up_legs", "first_cell":
// "template" | "snapshot", "unconverged": "keep" | "replay"}, and the "substepping", "q_h" and
// "retiling" of every DEM-backed law.
constexpr std::string_view kKeys[] = {"name", "law", "library",     "template", "cell",    "tolerance",
                                      "error_budget", "k",  "sample_span", "substepping", "q_h", "retiling",
                                      "fallback"};

std::unique_ptr<ConstitutiveLaw> read(const JsonNode& material, const LawContext& scene) {
  SurrogateLawSettings s;
  s.live = read_live_settings(material);
  s.tolerance = material.number("tolerance", Range::at_least(0));
  s.error_budget = material.number_or("error_budget", s.error_budget, Range::positive());
  s.surrogate.k = static_cast<std::size_t>(material.integer_or("k", static_cast<std::int64_t>(s.surrogate.k), 1, 1000));
  s.sample_span = static_cast<std::size_t>(
      material.integer_or("sample_span", static_cast<std::int64_t>(s.sample_span), 1, 1000));
  if (const auto fallback = material.find("fallback")) {
    fallback->allow_only({"return_after", "warm_start", "stress_tolerance", "max_servo_steps", "servo_inertial_number",
                          "catch_up_steps", "catch_up_legs", "first_cell", "unconverged"});
    s.return_after = static_cast<int>(fallback->integer_or("return_after", s.return_after, 0, 1000000000));
    if (const auto mode = fallback->find("warm_start")) {
      const std::string name = mode->string();
      if (name != "state" && name != "replay") mode->fail("expected \"state\" or \"replay\"");
      s.warm_start = name == "state" ? SurrogateLawSettings::WarmStart::state : SurrogateLawSettings::WarmStart::replay;
    }
    StateWarmStartSettings& w = s.state_warm_start;
    if (fallback->has("stress_tolerance")) w.stress_tolerance = fallback->number("stress_tolerance", Range::positive());
    w.max_servo_steps = fallback->integer_or("max_servo_steps", w.max_servo_steps, 1, 1000000000);
    w.servo_inertial_number = fallback->number_or("servo_inertial_number", w.servo_inertial_number, Range::positive());
    w.catch_up_steps = fallback->integer_or("catch_up_steps", w.catch_up_steps, 1, 1000000000);
    w.catch_up_legs = fallback->integer_or("catch_up_legs", w.catch_up_legs, 1, 1000000000);
    if (const auto first = fallback->find("first_cell")) {
      const std::string name = first->string();
      if (name != "template" && name != "snapshot") first->fail("expected \"template\" or \"snapshot\"");
      w.first_cell = name == "template" ? StateWarmStartSettings::FirstCell::template_caught_up
                                        : StateWarmStartSettings::FirstCell::nearest_snapshot;
    }
    if (const auto unconverged = fallback->find("unconverged")) {
      const std::string name = unconverged->string();
      if (name != "keep" && name != "replay") unconverged->fail("expected \"keep\" or \"replay\"");
      w.replay_unconverged = name == "replay";
    }
  }
  const JsonNode lib = material.at("library", "a library directory (string)");
  const std::int64_t id = material.at("template", "a template id (integer)").integer(1);
  std::optional<dem::Material> expected;
  if (material.has("cell")) expected = app::load_cell_input(scene.folder / material.at("cell", "").string()).material;
  std::unique_ptr<LibraryLink> link;
  surrogate::Dataset dataset;
  std::vector<StateSnapshot> snapshots;
  try {
    link = std::make_unique<LibraryLink>(scene.folder / lib.string(), id, expected ? &*expected : nullptr);
    dataset = link->locked([&](db::Library& library) { return surrogate::reindex(library, s.sample_span); });
    if (s.warm_start == SurrogateLawSettings::WarmStart::state &&
        s.state_warm_start.first_cell == StateWarmStartSettings::FirstCell::nearest_snapshot)
      snapshots = link->state_snapshots();
  } catch (const db::StoreError& e) {
    lib.fail(e.what());
  }
  require_compatible(material, link->template_cell().material(), scene.effects, "the library " + lib.string(), s.live);
  return common::at_node(material,
                         [&] { return std::make_unique<SurrogateLaw>(link->template_cell(), std::move(dataset), s, std::move(snapshots)); });
}

const LawRegistration registration{{"surrogate", kKeys, true, &read}};

}  // namespace

}  // namespace grainbank::mpm
