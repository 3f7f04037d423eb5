// What a surrogate run says of itself: the length-scale fit at its start, and at its end how its
// error estimate and its library's samples met the states where its cells ran live.
#include <algorithm>
#include <iomanip>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "mpm_solver/dem_laws/surrogate_law.hpp"

namespace grainbank::mpm {

namespace {

// The features in which a noted share of the live states lay beyond the library's tails, as
// "Z below in 55 %", the largest shares first.
std::vector<std::string> features_beyond(const surrogate::LibraryReach& reach, double noted) {
  std::vector<std::pair<double, std::string>> sides;
  for (std::size_t j = 0; j < surrogate::kFeatureCount; ++j) {
    const std::string name(surrogate::kFeatureNames[j]);
    if (reach.features[j].below >= noted) sides.emplace_back(reach.features[j].below, name + " below");
    if (reach.features[j].above >= noted) sides.emplace_back(reach.features[j].above, name + " above");
  }
  std::stable_sort(sides.begin(), sides.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<std::string> out;
  for (const auto& [share, side] : sides) {
    std::ostringstream text;
    text << side << " in " << std::fixed << std::setprecision(0) << 100 * share << " %";
    out.push_back(text.str());
  }
  return out;
}

// `probe_coverage`: the length-scale fit's coverage on its probes, when there was a fit.
void add_estimate(const surrogate::EstimateCalibration& a, std::optional<double> probe_coverage, LawReport& report) {
  report.figures.insert(report.figures.end(),
                        {{"estimate_on_live_states/samples", static_cast<double>(a.samples)},
                         {"estimate_on_live_states/coverage", a.coverage},
                         {"estimate_on_live_states/median_error_over_estimate", a.median_error_over_estimate},
                         {"estimate_on_live_states/median_error", a.median_error},
                         {"estimate_on_live_states/median_estimate", a.median_estimate}});
  if (a.coverage >= 0.5) return;
  std::ostringstream note;
  note << std::fixed << std::setprecision(0) << "where the run went live, the library's error estimate covered "
       << 100 * a.coverage << " % of its errors";
  if (probe_coverage) note << " (" << 100 * *probe_coverage << " % on the length-scale fit's probes)";
  note << std::setprecision(1) << ", their median " << a.median_error_over_estimate
       << " times the estimate: on this scene's hardest states the estimate is optimistic, and a tolerance in it "
          "bounds less than it says (summary.json: coupling/laws/estimate_on_live_states)";
  report.notes.push_back(note.str());
}

void add_reach(const surrogate::LibraryReach& reach, LawReport& report) {
  const std::string root = "live_states_beyond_library/";
  report.figures.insert(report.figures.end(), {{root + "states", static_cast<double>(reach.states)},
                                               {root + "tail", reach.tail},
                                               {root + "any", reach.beyond_any}});
  for (std::size_t j = 0; j < surrogate::kFeatureCount; ++j) {
    const std::string name(surrogate::kFeatureNames[j]);
    report.figures.insert(report.figures.end(), {{root + name + "/below", reach.features[j].below},
                                                 {root + name + "/above", reach.features[j].above}});
  }
  const std::vector<std::string> sides = features_beyond(reach, SurrogateLaw::kReachNoted);
  if (sides.empty()) return;
  std::ostringstream note;
  note << "where the run went live, its states lay beyond the library's samples (beyond all but " << std::fixed
       << std::setprecision(0) << 100 * reach.tail << " % of them at either end): ";
  for (std::size_t i = 0; i < sides.size(); ++i) note << (i ? ", " : "") << sides[i];
  note << " of those states. The surrogate extrapolates there, and its error estimate cannot say by how much; "
          "library paths that reach such states would let it answer them (summary.json: "
          "coupling/laws/live_states_beyond_library)";
  report.notes.push_back(note.str());
}

}  // namespace

void SurrogateLaw::finish() {
  if (library_.empty() || learned_.empty()) return;
  live_states_ = {surrogate::audit_estimate(index_->constants(), library_, index_->scales(), settings_.surrogate,
                                           learned_, kAuditedStates),
                  surrogate::library_reach(library_, learned_, kReachTail)};
}

LawReport SurrogateLaw::end_report() const {
  LawReport report;
  if (!live_states_) return report;
  add_estimate(live_states_->estimate, fit_ ? std::optional(fit_->coverage) : std::nullopt, report);
  add_reach(live_states_->reach, report);
  return report;
}

LawReport SurrogateLaw::start_report() const {
  LawReport report;
  if (!fit_) return report;
  report.figures = {{"length_scale_fit/seed", static_cast<double>(settings_.fit.seed)},
                    {"length_scale_fit/probes", static_cast<double>(fit_->probes)},
                    {"length_scale_fit/initial_loss", fit_->initial_loss},
                    {"length_scale_fit/loss", fit_->loss},
                    {"length_scale_fit/gain", fit_->gain},
                    {"length_scale_fit/coverage", fit_->coverage},
                    {"length_scale_fit/median_error_over_estimate", fit_->median_error_over_estimate}};
  std::string undetermined;
  for (std::size_t j = 0; j < surrogate::kFeatureCount; ++j) {
    const std::string name(surrogate::kFeatureNames[j]);
    const surrogate::ScaleEvidence& e = fit_->evidence[j];
    report.figures.insert(report.figures.end(), {{"length_scales/" + name + "/scale", fit_->scales[j]},
                                                 {"length_scales/" + name + "/finer", e.finer},
                                                 {"length_scales/" + name + "/coarser", e.coarser}});
    if (!e.determined()) undetermined += (undetermined.empty() ? "" : ", ") + name;
  }
  if (!undetermined.empty()) {
    std::ostringstream note;
    note.precision(2);
    note << "the length-scale fit is a draw along " << undetermined << ": the library's " << fit_->probes
         << " probes move its loss by less than two standard errors when one of these scales is made e times finer or "
            "coarser (the fit's gain over its start: "
         << fit_->gain << " standard errors). Runs with other \"fit_seed\" values show what the draw moves; the "
         << "fit, and how often its error estimate covered the probes' errors (" << std::fixed << std::setprecision(0)
         << 100 * fit_->coverage << " %), are in summary.json (coupling/laws/length_scales, length_scale_fit)";
    report.notes.push_back(note.str());
  }
  return report;
}

}  // namespace grainbank::mpm
