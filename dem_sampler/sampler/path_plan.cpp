#include "dem_sampler/sampler/path_plan.hpp"

#include "dem_sampler/driver/path_driver.hpp"

namespace grainbank::sampler {

using common::JsonNode;
using common::Range;

nlohmann::json to_json(const PathPlan& plan) {
  nlohmann::json segments = nlohmann::json::array();
  for (const app::PathSegment& s : plan.path.segments) {
    nlohmann::json segment = {{"L", {{s.L(0, 0), s.L(0, 1)}, {s.L(1, 0), s.L(1, 1)}}}, {"duration", s.duration}};
    if (s.pressure > 0) segment["pressure"] = s.pressure;  // absent otherwise: older specs keep their hash
    segments.push_back(segment);
  }
  const dem::Substepping& q = plan.path.substepping;
  return {{"segments", segments},
          {"record_interval", plan.path.record_interval},
          {"snapshot_interval", plan.snapshot_interval},
          {"substepping", {{"q_t", q.q_t}, {"q_n", q.q_n}, {"q_sigma", q.q_sigma}}}};
}

PathPlan plan_from_json(const JsonNode& node) {
  node.allow_only({"segments", "record_interval", "snapshot_interval", "substepping"});
  PathPlan plan;
  const JsonNode segments = node.at("segments", "a non-empty array of {L, duration}");
  const std::size_t count = segments.array_size("a non-empty array of {L, duration}");
  if (count == 0) segments.fail_expected("a non-empty array of {L, duration}");
  for (std::size_t k = 0; k < count; ++k) plan.path.segments.push_back(app::read_segment(segments.at(k)));
  plan.path.record_interval = node.number("record_interval", Range::positive());
  plan.snapshot_interval = static_cast<long>(node.integer_or("snapshot_interval", 0, 0));
  plan.path.substepping = app::read_substepping(node);
  return plan;
}

long record_count(const PathPlan& plan) { return app::increment_count(plan.path) + 1; }

}  // namespace grainbank::sampler
