#include "dem_sampler/sampler/paths_input.hpp"

#include <algorithm>
#include <numbers>
#include <span>

#include "dem_sampler/sampler/path_generator.hpp"
#include "dem_sampler/sampler/state_probes.hpp"

namespace grainbank::sampler {
namespace {

using common::JsonNode;
using common::Range;

// What an entry inherits from the top level unless it says otherwise.
struct Defaults {
  std::optional<double> record_interval;
  long snapshot_interval = 0;
  dem::Substepping substepping;
};

Defaults read_defaults(const JsonNode& root) {
  Defaults d;
  if (const auto dt = root.find("record_interval")) d.record_interval = dt->number(Range::positive());
  d.snapshot_interval = static_cast<long>(root.integer_or("snapshot_interval", 0, 0));
  d.substepping = app::read_substepping(root);
  return d;
}

// The entry's own value, or the inherited one.
Defaults entry_settings(const JsonNode& entry, const Defaults& defaults) {
  Defaults d = defaults;
  if (const auto dt = entry.find("record_interval")) d.record_interval = dt->number(Range::positive());
  if (!d.record_interval)
    entry.fail_missing("record_interval", "a positive number [s] (here or at the top level)");
  d.snapshot_interval = static_cast<long>(entry.integer_or("snapshot_interval", defaults.snapshot_interval, 0));
  if (entry.has("substepping")) d.substepping = app::read_substepping(entry);
  return d;
}

PathPlan plan_with(const Defaults& d) {
  PathPlan plan;
  plan.path.record_interval = *d.record_interval;
  plan.path.substepping = d.substepping;
  plan.snapshot_interval = d.snapshot_interval;
  return plan;
}

PathPlan read_path(const JsonNode& entry, const Defaults& defaults) {
  entry.allow_only({"segments", "replay", "record_interval", "snapshot_interval", "substepping"});
  const auto segments = entry.find("segments");
  const auto replay = entry.find("replay");
  if (segments && replay) replay->fail("give either segments or replay, not both");
  if (!segments && !replay)
    entry.fail_missing("segments", "a non-empty array of {L, duration | strain} (or \"replay\": an array of L)");
  PathPlan plan = plan_with(entry_settings(entry, defaults));
  const JsonNode list = segments ? *segments : *replay;
  const char* expected = segments ? "a non-empty array of {L, duration | strain}"
                                  : "a non-empty array of in-plane velocity gradients [[Lxx, Lxy], [Lyx, Lyy]]";
  const std::size_t count = list.array_size(expected);
  if (count == 0) list.fail_expected(expected);
  for (std::size_t k = 0; k < count; ++k) {
    if (segments)
      plan.path.segments.push_back(app::read_segment(list.at(k)));
    else  // one increment per L: exactly the history a material point imposed
      plan.path.segments.push_back({app::read_in_plane_gradient(list.at(k)), plan.path.record_interval});
  }
  return plan;
}

std::vector<PathPlan> read_generator(const JsonNode& entry, const Defaults& defaults) {
  entry.allow_only({"count", "start", "rate", "strain", "segments", "changes", "volumetric", "spin",
                    "record_interval", "snapshot_interval", "substepping"});
  const Defaults d = entry_settings(entry, defaults);
  GeneratorSpec g;
  g.record_interval = *d.record_interval;
  g.snapshot_interval = d.snapshot_interval;
  g.substepping = d.substepping;
  g.count = static_cast<long>(entry.at("count", "an integer >= 1").integer(1, 1'000'000));
  g.start = static_cast<std::uint64_t>(entry.integer_or("start", 0, 0, std::int64_t{1} << 40));
  const JsonNode rate = entry.at("rate", "an object {min, max} [1/s]");
  rate.allow_only({"min", "max"});
  g.min_rate = rate.number("min", Range::positive());
  g.max_rate = rate.number("max", Range::at_least(g.min_rate));
  g.strain = entry.number("strain", Range::positive());
  g.segments = static_cast<int>(entry.integer_or("segments", 1, 1, kMaxSegments));
  if (const auto changes = entry.find("changes")) {
    constexpr const char* kExpected = "a non-empty array of \"reversal\", \"rotation\" or \"fresh\"";
    const std::size_t n = changes->array_size(kExpected);
    if (n == 0) changes->fail_expected(kExpected);
    g.changes.clear();
    for (std::size_t k = 0; k < n; ++k) {
      const JsonNode item = changes->at(k);
      try {
        g.changes.push_back(direction_change_from(item.string()));
      } catch (const std::invalid_argument&) {
        item.fail_expected("\"reversal\", \"rotation\" or \"fresh\"");
      }
    }
  }
  g.volumetric = entry.number_or("volumetric", g.volumetric, Range::between(0, 1, false, false));
  g.spin = entry.number_or("spin", g.spin, Range::between(0, 1, false, false));
  return generate_paths(g);
}

// A non-empty array of numbers, each in `range`, times `scale`.
std::vector<double> number_list(const JsonNode& entry, const char* key, const char* expected, const Range& range,
                                double scale = 1) {
  const JsonNode list = entry.at(key, expected);
  const std::size_t n = list.array_size(expected);
  if (n == 0) list.fail_expected(expected);
  std::vector<double> values;
  for (std::size_t k = 0; k < n; ++k) values.push_back(scale * list.at(k).number(range));
  return values;
}

std::vector<PathPlan> read_probes(const JsonNode& entry, const Defaults& defaults) {
  entry.allow_only({"bases", "depths", "base_rate", "base_pressure", "psi", "beta", "rates", "probe_strain",
                    "record_interval", "snapshot_interval", "substepping"});
  const Defaults d = entry_settings(entry, defaults);
  ProbeSpec p;
  p.record_interval = *d.record_interval;
  p.snapshot_interval = d.snapshot_interval;
  p.substepping = d.substepping;
  constexpr const char* kBases =
      "a non-empty array of \"compression\", \"shear\", \"extension\", \"oedometric\" or \"held_shear\"";
  const JsonNode bases = entry.at("bases", kBases);
  const std::size_t n = bases.array_size(kBases);
  if (n == 0) bases.fail_expected(kBases);
  for (std::size_t k = 0; k < n; ++k) {
    const JsonNode item = bases.at(k);
    try {
      p.bases.push_back(probe_base_from(item.string()));
    } catch (const std::invalid_argument&) {
      item.fail_expected("\"compression\", \"shear\", \"extension\", \"oedometric\" or \"held_shear\"");
    }
  }
  constexpr double kDegree = std::numbers::pi / 180;
  const double max_psi = kMaxPlaneStrainPsi / kDegree;
  p.depths = number_list(entry, "depths", "a non-empty array of strains > 0", Range::positive());
  p.base_rate = entry.number("base_rate", Range::positive());
  const bool held = std::find(p.bases.begin(), p.bases.end(), ProbeBase::held_shear) != p.bases.end();
  if (held) p.base_pressure = entry.number("base_pressure", Range::positive());
  else if (entry.has("base_pressure")) entry.at("base_pressure", "").fail("base_pressure is read by the held_shear base only");
  p.psi = number_list(entry, "psi", "a non-empty array of angles [°] within ±67.79 (plane strain)",
                      Range::between(-max_psi, max_psi, false, false), kDegree);
  p.beta = number_list(entry, "beta", "a non-empty array of angles [°]", Range::between(-180, 180, false, false),
                       kDegree);
  p.rates = number_list(entry, "rates", "a non-empty array of rates > 0 [1/s]", Range::positive());
  p.probe_strain = entry.number("probe_strain", Range::positive());
  return probe_paths(p);
}

// The library stores each plan as its canonical spec, and the sampler that runs it reads that spec
// back. An entry whose fields give a spec that does not read back (a strain at an L so large that
// the segment lasts 0 s, a rate that overflows) is refused here, at its own pointer: registered, it
// would stay pending and stop every later `sample` of the library.
void require_runnable(const JsonNode& entry, std::span<const PathPlan> plans) {
  for (std::size_t k = 0; k < plans.size(); ++k) {
    const nlohmann::json spec = to_json(plans[k]);
    try {
      plan_from_json(JsonNode(spec, "its canonical spec"));
    } catch (const common::InputError& e) {
      const std::string which =
          plans.size() > 1 ? "its path " + std::to_string(k + 1) + " of " + std::to_string(plans.size()) : "its path";
      entry.fail(which + " cannot be run: " + e.what());
    }
  }
}

}  // namespace

std::vector<PathPlan> load_paths_file(const std::filesystem::path& file) {
  const nlohmann::json document = common::load_json_file(file);
  const JsonNode root(document, file.string());
  root.allow_only({"paths", "generators", "probes", "record_interval", "snapshot_interval", "substepping"});
  const Defaults defaults = read_defaults(root);
  std::vector<PathPlan> plans;
  if (const auto paths = root.find("paths")) {
    const std::size_t n = paths->array_size("an array of paths {segments | replay, ...}");
    for (std::size_t k = 0; k < n; ++k) {
      const JsonNode entry = paths->at(k);
      plans.push_back(read_path(entry, defaults));
      require_runnable(entry, std::span(&plans.back(), 1));
    }
  }
  if (const auto generators = root.find("generators")) {
    const std::size_t n = generators->array_size("an array of generators {count, rate, strain, ...}");
    for (std::size_t k = 0; k < n; ++k) {
      std::vector<PathPlan> generated = read_generator(generators->at(k), defaults);
      require_runnable(generators->at(k), generated);
      plans.insert(plans.end(), generated.begin(), generated.end());
    }
  }
  if (const auto probes = root.find("probes")) {
    const std::size_t n = probes->array_size("an array of state probes {bases, depths, psi, beta, rates, ...}");
    for (std::size_t k = 0; k < n; ++k) {
      std::vector<PathPlan> probed = read_probes(probes->at(k), defaults);
      require_runnable(probes->at(k), probed);
      plans.insert(plans.end(), probed.begin(), probed.end());
    }
  }
  if (plans.empty()) root.fail("no paths: give a non-empty \"paths\", \"generators\" or \"probes\" array");
  return plans;
}

}  // namespace grainbank::sampler
