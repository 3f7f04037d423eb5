// SurrogateLaw's checkpoint: what save_state writes and restore_state reads back, so that a restart
// continues bit for bit (the promise in surrogate_law.hpp).
#include <algorithm>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "mpm_solver/dem_laws/surrogate_law.hpp"
#include "mpm_solver/dem_laws/warm_start.hpp"

namespace grainbank::mpm {

namespace {

// Per point: slot, σ (9, row-major), φ, Z, D, live (0/1), steps inside the tolerance, error spent
// since its last live spell [Pa], live cell started by replay (0/1), live spell started by the
// budget (0/1); live cells as "cell_<slot>"; the replay histories as append_history writes them;
// the learned samples as rows features, answer, origin path, origin record, in insertion order;
// per kept cell: slot and the increments it has seen, the cell as "parked_<slot>"; per
// checkpoint: slot and the increments it has seen, the cell as "checkpoint_<slot>"; per step of a live
// cell's sample span, in order: slot, the state before it (σ, φ, Z, D), L (9, row-major), dt. And
// one row of what the learned samples' keys and answers were made with: p_ref, p_floor, d, ρ and
// the sample span.
constexpr std::size_t kStateColumns = 12;
constexpr std::size_t kPointColumns = 1 + kStateColumns + 5;
constexpr std::size_t kSampleColumns = surrogate::kFeatureCount + surrogate::kAnswerSize + 2;
constexpr std::size_t kKeptColumns = 2;  // per kept cell (parked or checkpoint): slot, increments seen
constexpr std::size_t kSpanColumns = 1 + kStateColumns + 9 + 1;
constexpr std::size_t kKeyingColumns = 5;
std::string cell_name(std::size_t slot) { return "cell_" + std::to_string(slot); }
std::string parked_cell_name(std::size_t slot) { return "parked_" + std::to_string(slot); }
std::string checkpoint_cell_name(std::size_t slot) { return "checkpoint_" + std::to_string(slot); }

void append_state(std::vector<double>& rows, const surrogate::PointState& state) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) rows.push_back(state.stress(i, j));
  rows.insert(rows.end(), {state.solid_fraction, state.coordination, state.damage});
}

std::vector<double> keying(const surrogate::FeatureConstants& c, std::size_t sample_span) {
  return {c.p_ref, c.p_floor, c.diameter, c.density, double(sample_span)};
}

std::string describe_keying(const std::vector<double>& k) {
  std::ostringstream s;
  s << "p_ref " << k.at(0) << " Pa, p_floor " << k.at(1) << " Pa, d " << k.at(2) << " m, rho " << k.at(3)
    << " kg/m^3, sample_span " << k.at(4);
  return s.str();
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
  out.write_table("surrogate_parked", parked, kKeptColumns);
  out.write_table("surrogate_checkpoints", checkpoints, kKeptColumns);
  out.write_table("surrogate_span", span, kSpanColumns);
  out.write_table("surrogate_keying", keying(index_->constants(), settings_.sample_span), kKeyingColumns);
}

void SurrogateLaw::restore_state(LawStateReader& in) {
  if (learned() > 0) throw std::logic_error("surrogate law: restore_state into a law that has already learned samples");
  // The learned samples are keys and answers made with the run's constants and span: resumed with
  // another pressure_floor or sample_span they would be keyed apart from the library's, silently.
  // (A file written before the table was kept has none to compare.)
  if (in.has_table("surrogate_keying")) {
    const std::vector<double> saved = in.read_table("surrogate_keying", kKeyingColumns);
    const std::vector<double> now = keying(index_->constants(), settings_.sample_span);
    if (saved != now)
      throw std::runtime_error("surrogate law: the restart's learned samples were made with " + describe_keying(saved) +
                               "; this scene gives " + describe_keying(now) +
                               ": resume with the library, pressure_floor and sample_span the run started with");
  }
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
  // The kept cells, each with the increments of its point's history it has seen.
  const auto restore_kept = [&](const std::string& table, std::string (*name)(std::size_t),
                                std::unique_ptr<dem::DemCell> Point::*kept, std::size_t Point::*seen) {
    for (Point& p : points_) (p.*kept).reset();
    const std::vector<double> rows = in.read_table(table, kKeptColumns);
    for (std::size_t r = 0; r < rows.size(); r += kKeptColumns) {
      const auto slot = static_cast<std::size_t>(rows[r]);
      Point& p = points_.at(slot);
      p.*seen = static_cast<std::size_t>(rows[r + 1]);
      p.*kept = std::make_unique<dem::DemCell>(model_.cell_from(in.read_cell(name(slot))));
    }
  };
  restore_kept("surrogate_parked", parked_cell_name, &Point::parked, &Point::parked_at);
  restore_kept("surrogate_checkpoints", checkpoint_cell_name, &Point::checkpoint, &Point::checkpoint_at);
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

}  // namespace grainbank::mpm
