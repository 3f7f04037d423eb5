#include "mpm_solver/app/audit_command.hpp"

#include <algorithm>
#include <fstream>
#include <functional>
#include <iomanip>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "database/audit/audit_report.hpp"
#include "mpm_solver/audit/run_audit.hpp"
#include "common/json_input.hpp"
#include "dem_sampler/driver/cell_input.hpp"
#include "mpm_solver/io/scene_input.hpp"
#include "mpm_solver/app/scene_overrides.hpp"
#include "database/store/audit_log.hpp"
#include "database/store/library.hpp"
#include "database/store/material_parameters.hpp"

namespace grainbank::mpm::app {

namespace {

const char* source_name(StressSource s) {
  switch (s) {
    case StressSource::analytic: return "analytic";
    case StressSource::live: return "live";
    case StressSource::hit: return "hit";
    case StressSource::miss: return "miss";
  }
  return "?";
}

io::AuditTrail read_trail(const std::filesystem::path& run) {
  const std::filesystem::path file = run / io::kAuditTrailFile;
  if (!std::filesystem::exists(file))
    throw common::InputError(file.string() +
                             ": not found; the run recorded no audit trail (add \"audit\": {\"points\": N} to its "
                             "scene and run it again)");
  io::AuditTrail trail = io::read_audit_trail(file);
  if (trail.start_time != 0)
    throw common::InputError(file.string() + ": the run resumed from a restart at t = " +
                             std::to_string(trail.start_time) +
                             " s, so its trail lacks the history before; audit a run started from t = 0");
  return trail;
}

// The run's scene with its DEM-backed materials live and their cell and library paths absolute; with
// `cell`, every one of them takes that cell instead of its library's template or its own cell.
nlohmann::json live_scene(const io::AuditTrail& trail, const std::optional<std::filesystem::path>& cell = {}) {
  const std::filesystem::path scene = trail.scene;
  SceneOverrides live;
  live.law = "live";
  if (cell) live.material = nlohmann::json{{"cell", std::filesystem::absolute(*cell).string()}};
  return apply_overrides(common::load_json_file(scene), scene.parent_path(), live);
}

// The noise floor's cell must be the reference's recipe with another packing: the same material and
// sphere count, or the floor would measure another material or cell size instead of the packing.
void check_floor_cell(const std::filesystem::path& file, const nlohmann::json& scene) {
  const grainbank::app::CellInput recipe = grainbank::app::load_cell_input(file);
  if (!recipe.preparation)
    throw common::InputError(file.string() + ": --floor-cell: expected a cell.json with a \"preparation\" (the "
                             "noise floor is the reference's recipe prepared with another seed), found a packing file");
  for (const auto& m : scene["materials"]) {
    if (m.value("law", "") != "live") continue;
    const std::string name = m.value("name", "?");
    dem::Material material;
    std::size_t spheres = 0;
    if (m.contains("library")) {
      db::Library library = db::Library::open(m["library"].get<std::string>());
      material = library.material();
      spheres = static_cast<std::size_t>(library.catalogue().template_row(m["template"].get<std::int64_t>()).spheres);
    } else {
      const grainbank::app::CellInput reference = grainbank::app::load_cell_input(m["cell"].get<std::string>());
      material = reference.material;
      spheres = reference.preparation ? reference.preparation->spheres : grainbank::app::build_cell(reference).size();
    }
    const std::vector<std::string> differences = db::material_differences(material, recipe.material);
    if (!differences.empty()) {
      std::string message = file.string() + ": --floor-cell: expected the material of \"" + name +
                            "\" (\"library\" below: the reference's), but ";
      for (std::size_t k = 0; k < differences.size(); ++k) message += (k ? "; " : "") + differences[k];
      throw common::InputError(message);
    }
    if (recipe.preparation->spheres != spheres)
      throw common::InputError(file.string() + ": preparation.spheres: expected " + std::to_string(spheres) +
                               " (the reference cell of \"" + name + "\"), got " +
                               std::to_string(recipe.preparation->spheres));
  }
}

// The reference slot of each audited point in `solver`, the scene loaded from `scene_file`.
std::function<audit::ReferenceSlot(std::uint32_t)> slots_in(Solver& solver, const std::string& scene_file) {
  return [&solver, scene_file](std::uint32_t id) {
    const auto& points = solver.points();
    const auto it = std::find_if(points.begin(), points.end(), [&](const MaterialPoint& p) { return p.id == id; });
    if (it == points.end())
      throw common::InputError(scene_file + ": has no material point " + std::to_string(id) +
                               " of the audit trail (was the scene changed after the run?)");
    return audit::ReferenceSlot{&solver.law(it->law), it->slot};
  };
}

// {"by_source": {"hit", "miss", "live"}, "cached", "all"}: the layout of the summary and of its noise floor.
nlohmann::json summaries_json(const audit::SourceSummaries& e) {
  using grainbank::audit::summary_of;
  return {{"by_source", {{"hit", summary_of(e.hit)}, {"miss", summary_of(e.miss)}, {"live", summary_of(e.live)}}},
          {"cached", summary_of(e.cached)},
          {"all", summary_of(e.all)}};
}

// The libraries of the scene's materials, each once.
std::set<std::string> libraries_of(const nlohmann::json& scene) {
  std::set<std::string> out;
  for (const auto& m : scene["materials"])
    if (m.contains("library")) out.insert(m["library"].get<std::string>());
  return out;
}

void write_stress(std::ostream& out, const PointStress& s) {
  out << ',' << s.in_plane(0, 0) << ',' << s.in_plane(1, 1) << ',' << s.in_plane(0, 1) << ',' << s.zz;
}

// With a noise floor, each row also has the other packing's error and stress.
void write_steps_csv(const audit::RunAudit& audit, const std::optional<audit::NoiseFloor>& floor,
                     const std::filesystem::path& file) {
  std::ofstream out(file);
  out << "point,step,time,source,relative_error,run_sxx,run_syy,run_sxy,run_szz,live_sxx,live_syy,live_sxy,live_szz";
  if (floor) out << ",noise_floor_relative_error,other_sxx,other_syy,other_sxy,other_szz";
  out << '\n' << std::setprecision(17);
  for (std::size_t i = 0; i < audit.steps.size(); ++i) {
    const audit::StepComparison& c = audit.steps[i];
    out << c.point << ',' << c.step << ',' << c.time << ',' << source_name(c.source) << ',' << c.relative_error;
    write_stress(out, c.run);
    write_stress(out, c.live);
    if (floor) {
      out << ',' << floor->relative_error[i];
      write_stress(out, floor->other[i]);
    }
    out << '\n';
  }
  if (!out) throw std::runtime_error(file.string() + ": cannot be written");
}

void print_report(const nlohmann::json& s, std::ostream& out) {
  const bool floor = s.contains("noise_floor");
  out << "audit of the run " << s["run"].get<std::string>() << ": " << s["points"].size() << " point(s), "
      << s["steps_compared"] << " point-steps re-run live\n"
      << "relative stress error (floor " << s["stress_floor_pa"].get<double>() << " Pa)      count     median        p95        max"
      << (floor ? "   noise floor: median        p95" : "") << "\n";
  const auto by = [](const nlohmann::json& summary, const std::string& key) -> const nlohmann::json& {
    return key == "cached" || key == "all" ? summary[key] : summary["by_source"][key];
  };
  for (const char* key : {"hit", "miss", "live", "cached", "all"}) {
    const auto& e = by(s, key);
    out << "  " << std::left << std::setw(34) << key << std::right << std::setw(8) << e["count"].get<std::size_t>()
        << std::setw(11) << std::setprecision(3) << e["median"].get<double>() << std::setw(11) << e["p95"].get<double>()
        << std::setw(11) << e["max"].get<double>();
    if (floor) {
      const auto& f = by(s["noise_floor"], key);
      out << std::setw(22) << f["median"].get<double>() << std::setw(11) << f["p95"].get<double>();
    }
    out << "\n";
  }
  if (floor)
    out << "noise floor: the same histories re-run by " << s["noise_floor"]["cell"].get<std::string>()
        << " (another packing), against the reference\n";
}

}  // namespace

nlohmann::json run_audit_command(const AuditCommandOptions& options, std::ostream& out) {
  const io::AuditTrail trail = read_trail(options.run);
  const std::filesystem::path directory = options.run / "audit";
  std::filesystem::create_directories(directory);
  const nlohmann::json scene = live_scene(trail);
  const std::filesystem::path scene_file = directory / "scene_live.json";
  std::ofstream(scene_file) << scene.dump(2) << '\n';
  if (options.floor_cell) check_floor_cell(*options.floor_cell, scene);
  const io::Scene reference = io::load_scene(scene_file);
  const audit::RunAudit audit = audit::audit_run(trail, slots_in(*reference.solver, trail.scene));

  std::optional<audit::NoiseFloor> floor;
  if (options.floor_cell) {
    const std::filesystem::path floor_file = directory / "scene_floor.json";
    std::ofstream(floor_file) << live_scene(trail, options.floor_cell).dump(2) << '\n';
    const io::Scene other = io::load_scene(floor_file);
    floor = audit::noise_floor(trail, audit, slots_in(*other.solver, trail.scene));
  }

  nlohmann::json summary = {{"kind", "mpm_run"},
                            {"run", std::filesystem::absolute(options.run).string()},
                            {"scene", trail.scene},
                            {"points", nlohmann::json::array()},
                            {"steps_compared", audit.steps.size()},
                            {"stress_floor_pa", audit.stress_floor},
                            {"outputs", {{"directory", std::filesystem::absolute(directory).string()}}}};
  summary.update(summaries_json(audit.errors));
  if (floor) {
    summary["noise_floor"] = summaries_json(floor->errors);
    summary["noise_floor"]["cell"] = std::filesystem::absolute(*options.floor_cell).string();
  }
  for (const io::PointTrail& p : trail.points) summary["points"].push_back(p.id);
  write_steps_csv(audit, floor, directory / "run_audit_steps.csv");
  nlohmann::json audit_ids = nlohmann::json::array();
  for (const std::string& lib : libraries_of(scene)) {
    db::Library library = db::Library::open(lib);
    audit_ids.push_back({{"library", lib}, {"audit_id", db::record_audit(library.catalogue(), summary)}});
  }
  summary["catalogue_rows"] = audit_ids;
  std::ofstream(directory / "run_audit.json") << summary.dump(2) << '\n';

  if (options.json) {
    out << summary.dump(2) << "\n";
  } else {
    print_report(summary, out);
    out << "wrote " << (directory / "run_audit.json").string() << " and " << (directory / "run_audit_steps.csv").string()
        << "\nfigures: /usr/bin/python3 " << GRAINBANK_PLOT_RUN_AUDIT_SCRIPT << " " << directory.string() << "\n";
  }
  return summary;
}

}  // namespace grainbank::mpm::app
