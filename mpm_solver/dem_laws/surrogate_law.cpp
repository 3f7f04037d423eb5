#include "mpm_solver/dem_laws/surrogate_law.hpp"

#include <algorithm>
#include <chrono>
#include <optional>
#include <span>
#include <stdexcept>

#include "mpm_solver/dem_laws/warm_start.hpp"

namespace grainbank::mpm {

namespace {

// Fewer than two samples tell nothing of their spread: no fit, unit scales.
std::optional<surrogate::LengthScaleFit> fit_of(const surrogate::Dataset& dataset, const SurrogateLawSettings& settings) {
  if (dataset.samples.size() < 2) return std::nullopt;
  return surrogate::fit_length_scales(dataset.constants, dataset.samples, settings.surrogate, settings.fit);
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
  fit_ = fit_of(dataset, settings_);
  index_ = std::make_unique<surrogate::SurrogateIndex>(
      dataset.constants, fit_ ? fit_->scales : surrogate::initial_length_scales(dataset.samples), settings_.surrogate);
  index_->insert(dataset.samples);
  library_ = std::move(dataset.samples);
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
    const bool inside = settings_.return_after > 0 && answer(p, L, increment.dt).hit;
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

  surrogate::SurrogateStep step = answer(p, L, increment.dt);
  const bool budget_spent = step.hit && p.spent + step.estimated_error > settings_.error_budget;
  bool beyond_budget_alone = false;  // a step whose own estimated error exceeds the budget
  if (budget_spent && warm_start_) {
    reanchor(p);
    step = answer(p, L, increment.dt);
    beyond_budget_alone = step.hit && step.estimated_error > settings_.error_budget;
  }
  const bool spell_on_budget = (budget_spent && !warm_start_) || beyond_budget_alone;
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

surrogate::SurrogateStep SurrogateLaw::answer(Point& p, const dem::Mat3& L, double dt) const {
  surrogate::SurrogateStep step = surrogate::surrogate_step(*index_, p.state, L, dt, settings_.tolerance, p.neighbours);
  const std::vector<std::size_t>& found = step.prediction.neighbour_ids;
  if (!found.empty()) p.neighbours.assign(found.begin(), found.end());
  return step;
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

}  // namespace grainbank::mpm
