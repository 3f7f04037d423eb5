#include "dem_sampler/sampler/template_builder.hpp"

#include <algorithm>
#include <fstream>
#include <numeric>
#include <sstream>

#include "database/store/material_parameters.hpp"

namespace grainbank::sampler {
namespace {

nlohmann::json spec_json(const dem::PreparationSpec& s) {
  return {{"spheres", s.spheres},
          {"diameter", {{"min", s.min_diameter}, {"max", s.max_diameter}}},
          {"pressure", s.pressure},
          {"seed", s.seed},
          {"initial_solid_fraction", s.initial_solid_fraction},
          {"compression_friction", s.compression_friction},
          {"pressure_tolerance", s.pressure_tolerance},
          {"unbalanced_force_tolerance", s.unbalanced_force_tolerance},
          {"inertial_number", s.inertial_number},
          {"local_damping", s.local_damping},
          {"q_t", s.q_t},
          {"skin", s.skin},
          {"max_steps", s.max_steps}};
}

std::string file_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TemplateSummary summarize(const dem::DemCell& cell) {
  TemplateSummary s;
  const dem::CellMeasures m = cell.measures();
  s.spheres = cell.size();
  s.solid_fraction = m.solid_fraction;
  s.coordination = m.coordination;
  s.pressure = dem::pressure_of(m.stress);
  s.bonds = m.bonds;
  const auto& r = cell.radii();
  s.min_radius = *std::min_element(r.begin(), r.end());
  s.max_radius = *std::max_element(r.begin(), r.end());
  s.mean_radius = std::accumulate(r.begin(), r.end(), 0.0) / static_cast<double>(r.size());
  return s;
}

}  // namespace

nlohmann::json preparation_identity(const app::CellInput& input) {
  if (input.preparation) return {{"preparation", spec_json(*input.preparation)}};
  // The file's content, not its name: the same packing moved elsewhere is the same template.
  return {{"packing", {{"content_hash", db::text_hash(file_text(*input.packing))}, {"skin", input.packing_skin}}}};
}

TemplateSummary prepare_template(db::Library& library, const std::string& shard_name, const app::CellInput& input,
                                 const dem::PreparationObserver& observer) {
  library.require_material(input.material, "this cell");
  const nlohmann::json identity = preparation_identity(input);
  for (const db::TemplateRow& row : library.catalogue().templates()) {
    if (row.parameter_hash != library.parameter_hash()) continue;
    const nlohmann::json stored = nlohmann::json::parse(row.preparation, nullptr, false);
    if (!stored.is_discarded() && stored.contains("identity") && stored["identity"] == identity) {
      TemplateSummary s = describe_template(library, row.id);
      s.reused = true;
      return s;
    }
  }
  dem::PreparationReport report;
  dem::DemCell cell = input.preparation ? dem::prepare_cell(input.material, *input.preparation, &report, observer)
                                        : app::build_cell(input, observer);
  TemplateSummary s = summarize(cell);
  nlohmann::json preparation = {{"identity", identity},
                                {"report",
                                 {{"compression_steps", report.compression_steps},
                                  {"relaxation_steps", report.relaxation_steps},
                                  {"bonds", s.bonds},
                                  {"solid_fraction", s.solid_fraction},
                                  {"coordination", s.coordination},
                                  {"pressure", s.pressure}}}};
  // Opened only now: a shard open for writing cannot be read by describe_template above.
  db::ShardWriter writer(library, shard_name);
  s.id = writer.add_template(input.material, preparation, db::StoredCell{cell.state(), cell.skin()});
  return s;
}

TemplateSummary describe_template(db::Library& library, std::int64_t template_id) {
  TemplateSummary s = summarize(library.restore(library.template_cell(template_id)));
  s.id = template_id;
  return s;
}

}  // namespace grainbank::sampler
