#include "dem_sampler/driver/path_input.hpp"

#include <sstream>

#include "common/json_input.hpp"

namespace grainbank::app {
namespace {

using common::JsonNode;
using common::Range;

}  // namespace

dem::Mat3 read_in_plane_gradient(const JsonNode& node) {
  constexpr const char* kShape = "a 2x2 array [[Lxx, Lxy], [Lyx, Lyy]] [1/s]";
  if (node.array_size(kShape) != 2) node.fail_expected(kShape);
  dem::Mat3 L = dem::Mat3::Zero();
  for (std::size_t r = 0; r < 2; ++r) {
    const JsonNode row = node.at(r);
    if (row.array_size(kShape) != 2) row.fail_expected("a row of 2 numbers");
    for (std::size_t c = 0; c < 2; ++c) L(static_cast<int>(r), static_cast<int>(c)) = row.at(c).number();
  }
  return L;
}

PathSegment read_segment(const JsonNode& node) {
  node.allow_only({"L", "duration", "strain", "pressure"});
  PathSegment segment;
  segment.L = read_in_plane_gradient(node.at("L", "a 2x2 array [[Lxx, Lxy], [Lyx, Lyy]] [1/s]"));
  segment.pressure = node.number_or("pressure", 0.0, Range::positive());
  if (segment.pressure > 0 && !(strain_rate_norm(segment.L) > 0))
    node.at("pressure", "").fail("a pressure-controlled segment needs a stretching L to servo (L has no symmetric part)");
  const auto duration = node.find("duration");
  const auto strain = node.find("strain");
  if (duration && strain) strain->fail("give either duration or strain, not both");
  if (duration) {
    segment.duration = duration->number(Range::positive());
  } else if (strain) {
    const double target = strain->number(Range::positive());
    const double rate = strain_rate_norm(segment.L);
    if (!(rate > 0)) strain->fail("L has no symmetric part (a pure rotation never reaches a strain); give a duration");
    segment.duration = target / rate;
  } else {
    node.fail_missing("duration", "a positive number [s] (or \"strain\": a positive number)");
  }
  return segment;
}

dem::Substepping read_substepping(const JsonNode& root) {
  dem::Substepping q;
  const auto node = root.find("substepping");
  if (!node) return q;
  node->allow_only({"q_t", "q_n", "q_sigma"});
  q.q_t = node->number_or("q_t", q.q_t, Range::between(0, dem::kMaxTimeStepFactor, true, false));
  q.q_n = static_cast<int>(node->integer_or("q_n", q.q_n, 1, 1'000'000));
  q.q_sigma = node->number_or("q_sigma", q.q_sigma, Range::between(0, 1, true, false));
  return q;
}

void require_stable_q_t(const JsonNode& holder, double q_t, double restitution) {
  const auto error = dem::time_step_factor_error(q_t, restitution);
  if (!error) return;
  if (const auto node = holder.find("q_t")) node->fail(*error);
  std::ostringstream msg;
  msg << "q_t (default " << q_t << "): " << *error;
  holder.fail(msg.str());
}

double strain_rate_norm(const dem::Mat3& L) { return (0.5 * (L + L.transpose())).norm(); }

PathSpec load_path(const std::filesystem::path& file) {
  const nlohmann::json document = common::load_json_file(file);
  const JsonNode root(document, file.string());
  root.allow_only({"segments", "record_interval", "substepping"});
  PathSpec path;
  const JsonNode segments = root.at("segments", "a non-empty array of {L, duration | strain}");
  const std::size_t count = segments.array_size("a non-empty array of {L, duration | strain}");
  if (count == 0) segments.fail_expected("a non-empty array of {L, duration | strain}");
  for (std::size_t k = 0; k < count; ++k) path.segments.push_back(read_segment(segments.at(k)));
  path.record_interval = root.number("record_interval", Range::positive());
  path.substepping = read_substepping(root);
  return path;
}

}  // namespace grainbank::app
