// `mpm_solver audit RUN` (issue 7): the audit trail of a run re-run by live cells. A live run is
// reproduced bit for bit, so any stress the trail did not get from a live cell of the same history
// shows up as an error at exactly its point-step; a cache run is compared at every cached
// point-step and the audit lands in its library's catalogue; runs that cannot be audited are
// refused with the remedy.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "mpm_solver/app/audit_command.hpp"
#include "common/json_input.hpp"
#include "common/temporary_directory.hpp"
#include "tests/mpm/coupling_test_util.hpp"
#include "mpm_solver/io/audit_trail.hpp"
#include "mpm_solver/io/scene_input.hpp"
#include "mpm_solver/app/run_command.hpp"
#include "database/store/audit_log.hpp"

namespace grainbank::mpm::app {
namespace {

namespace fs = std::filesystem;

constexpr int kSteps = 30;

// Eight points of a block falling onto a floor under gravity, with `material` (a JSON object body).
std::string scene_json(const std::string& material, int audited) {
  std::ostringstream s;
  s << R"({
    "grid": {"origin": [0, 0], "cell_size": 0.1, "cells": [6, 6]},
    "time": {"end": )" << kSteps * 1e-4 << R"(, "output_interval": 1, "max_time_step": 1e-4},
    "effects": {"gravity": true, "boundary_friction": true},
    "gravity": {"g": [0, -9.81]},
    "materials": [{"name": "snow", )" << material << R"(, "substepping": {"q_t": 0.1, "q_n": 1, "q_sigma": 0.2}}],
    "regions": [{"material": "snow", "rectangle": {"min": [0.2, 0.2], "max": [0.4, 0.3]}, "points_per_cell": 2,
                 "velocity": [0.05, -0.3]}],
    "obstacles": [{"line": [[0, 0.195], [0.6, 0.195]], "k_n": 2e5, "k_t": 2e5, "friction": 0.5, "damping": 0.5}],
    "audit": {"points": )" << audited << R"(}
  })";
  return s.str();
}

class RunAudit : public ::testing::Test {
 protected:
  void SetUp() override {
    const dem::DemCell& cell = testing::small_snow_cell();
    library_ = dir_.path() / "lib";
    template_id_ = testing::create_library(library_, cell);
  }
  nlohmann::json run(const std::string& material, int audited, const std::string& name) {
    RunOptions o;
    o.scene = dir_.write(name + ".json", scene_json(material, audited));
    o.out = dir_.path() / name;
    o.progress = false;
    return run_scene(o);
  }
  nlohmann::json audit(const std::string& name) {
    std::ostringstream text;
    return run_audit_command({dir_.path() / name, false, {}}, text);
  }
  nlohmann::json audit_with_floor(const std::string& name, const fs::path& floor_cell) {
    std::ostringstream text;
    return run_audit_command({dir_.path() / name, false, floor_cell}, text);
  }
  // The recipe of the library's template (dem::snow_material, dem::snow_preparation(20, 9)) as a
  // cell.json, with another seed, size or friction.
  fs::path recipe(const std::string& name, int seed, int spheres = 20, double friction = 0.2) {
    std::ostringstream s;
    s << R"({"material": {"density": 920, "k_n": 2000, "k_t": 600, "restitution": 0.3, "friction": )" << friction
      << R"(, "contact_weight": 0.5, "bond": {"tensile_strength": 8e-4, "shear_strength": 9.6e-4, "exponent": 2,
              "bonding_distance": 0.05}},
        "effects": {"cohesion": true},
        "preparation": {"spheres": )" << spheres << R"(, "diameter": {"min": 3.4e-4, "max": 4.0e-4}, "pressure": 1000,
                        "seed": )" << seed << R"(, "inertial_number": 0.01}})";
    return dir_.write(name + ".json", s.str());
  }
  std::string library_material(const std::string& law, const std::string& extra = "") const {
    return R"("law": ")" + law + R"(", "library": ")" + library_.string() + R"(", "template": )" +
           std::to_string(template_id_) + extra;
  }

  TemporaryDirectory dir_{"gb_run_audit"};
  fs::path library_;
  std::int64_t template_id_ = 0;
};

TEST_F(RunAudit, ALiveRunIsReproducedBitForBitAndACorruptedStepIsFoundExactly) {
  const nlohmann::json summary = run(library_material("live"), 3, "live");
  ASSERT_EQ(summary["steps"], kSteps);
  const fs::path trail_file = dir_.path() / "live" / io::kAuditTrailFile;
  ASSERT_EQ(summary["audit_trail"], trail_file.string());

  const nlohmann::json clean = audit("live");
  EXPECT_EQ(clean["steps_compared"], 3 * kSteps);
  EXPECT_EQ(clean["by_source"]["live"]["count"], 3 * kSteps);
  EXPECT_EQ(clean["all"]["max"].get<double>(), 0.0);
  EXPECT_GT(clean["stress_floor_pa"].get<double>(), 0.0);

  // One stored stress changed by 1 % of its norm: exactly that point-step is off, by about 1 %.
  io::AuditTrail trail = io::read_audit_trail(trail_file);
  io::TrailStep& step = trail.points[1].steps[17];
  const double norm = std::hypot(step.stress.in_plane.norm(), step.stress.zz);
  step.stress.zz += 0.01 * norm;
  io::write_audit_trail(trail_file, trail);  // replaces the run's trail
  const nlohmann::json corrupted = audit("live");
  EXPECT_NEAR(corrupted["all"]["max"].get<double>(), 0.01, 1e-6);
  std::ifstream csv(dir_.path() / "live" / "audit" / "run_audit_steps.csv");
  std::string line;
  std::getline(csv, line);
  int off = 0;
  while (std::getline(csv, line)) {
    std::stringstream fields(line);
    std::string point, index, time, source, error;
    std::getline(fields, point, ','), std::getline(fields, index, ','), std::getline(fields, time, ',');
    std::getline(fields, source, ','), std::getline(fields, error, ',');
    if (std::stod(error) == 0) continue;
    ++off;
    EXPECT_EQ(std::stoul(point), trail.points[1].id);
    EXPECT_EQ(index, "17");
  }
  EXPECT_EQ(off, 1);
}

TEST_F(RunAudit, ACacheRunIsComparedAtEveryCachedPointStepAndRecordedInTheCatalogue) {
  // The library learns this scene from a hybrid run (every point live, responses enriched); on an
  // empty library its points turn live from the template at their first step, so they are live
  // cells of their own history and the audit finds them exact ...
  run(library_material("hybrid", R"(, "enrich": true)"), 1, "hybrid");
  const nlohmann::json hybrid = audit("hybrid");
  EXPECT_EQ(hybrid["by_source"]["live"]["count"], kSteps);
  EXPECT_LE(hybrid["all"]["max"].get<double>(), 1e-12);
  // ... and answers the cache run, which the audit re-runs live.
  run(library_material("cache", R"(, "lookup": {"k": 4, "tolerance": 1})"), 4, "cache");
  const nlohmann::json s = audit("cache");
  EXPECT_EQ(s["steps_compared"], 4 * kSteps);
  EXPECT_EQ(s["cached"]["count"], 4 * kSteps);
  EXPECT_EQ(s["by_source"]["hit"]["count"].get<int>() + s["by_source"]["miss"]["count"].get<int>(), 4 * kSteps);
  EXPECT_EQ(s["by_source"]["live"]["count"], 0);
  const double p95 = s["cached"]["p95"].get<double>(), max = s["cached"]["max"].get<double>();
  EXPECT_TRUE(std::isfinite(max));
  EXPECT_GT(max, 0.0);  // a cache is not a live cell
  EXPECT_LE(s["cached"]["median"].get<double>(), p95);
  EXPECT_LE(p95, max);

  db::Library library = db::Library::open(library_);
  const std::vector<db::AuditRow> rows = db::audits(library.catalogue());
  ASSERT_EQ(rows.size(), 2u);  // the hybrid run's audit, then the cache run's
  const nlohmann::json details = nlohmann::json::parse(rows[1].details);
  EXPECT_EQ(details["kind"], "mpm_run");
  EXPECT_EQ(details["cached"], s["cached"]);
  EXPECT_EQ(s["catalogue_rows"][0]["audit_id"], rows[1].id);
}

TEST_F(RunAudit, TheNoiseFloorIsZeroForTheSamePackingAndPositiveForAnother) {
  run(library_material("live"), 3, "live");
  // The reference's own recipe and seed: the same cell, so the floor vanishes at every step.
  const nlohmann::json same = audit_with_floor("live", recipe("seed9", 9));
  EXPECT_EQ(same["noise_floor"]["all"]["count"], 3 * kSteps);
  EXPECT_EQ(same["noise_floor"]["all"]["max"].get<double>(), 0.0);
  // Another packing of the recipe answers the same histories differently; the live run is its own
  // reference, so it lies below that floor.
  const nlohmann::json other = audit_with_floor("live", recipe("seed10", 10));
  const nlohmann::json& floor = other["noise_floor"];
  EXPECT_EQ(floor["by_source"]["live"]["count"], 3 * kSteps);
  EXPECT_GT(floor["all"]["median"].get<double>(), 0.0);
  EXPECT_TRUE(std::isfinite(floor["all"]["max"].get<double>()));
  EXPECT_EQ(other["all"]["max"].get<double>(), 0.0);
  EXPECT_EQ(other["stress_floor_pa"], same["stress_floor_pa"]);  // the floor cell does not move the reference
  std::ifstream csv(dir_.path() / "live" / "audit" / "run_audit_steps.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_NE(header.find(",noise_floor_relative_error,other_sxx,other_syy,other_sxy,other_szz"), std::string::npos) << header;

  // A cell of another material or size would measure that, not the packing: refused, naming it.
  for (const auto& [cell, expected] :
       {std::pair{recipe("friction", 10, 20, 0.3), std::string("contact.friction")},
        std::pair{recipe("bigger", 10, 24), std::string("preparation.spheres: expected 20")}}) {
    try {
      audit_with_floor("live", cell);
      FAIL() << "took " << cell << " as the floor";
    } catch (const common::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(cell.string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
  // The audit written before the refusals is still there.
  EXPECT_EQ(common::load_json_file(dir_.path() / "live" / "audit" / "run_audit.json")["noise_floor"], floor);
}

TEST_F(RunAudit, RunsThatCannotBeAuditedAreRefusedWithTheRemedy) {
  RunOptions o;
  nlohmann::json scene = nlohmann::json::parse(scene_json(library_material("live"), 1));
  scene.erase("audit");
  o.scene = dir_.write("plain.json", scene.dump());
  o.out = dir_.path() / "plain";
  o.progress = false;
  run_scene(o);
  try {
    audit("plain");
    FAIL() << "audited a run without a trail";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("add \"audit\": {\"points\": N} to its scene"), std::string::npos) << e.what();
  }

  // A run resumed from a restart has no history before it.
  run(library_material("live"), 2, "first");
  RunOptions resumed;
  resumed.scene = dir_.path() / "first.json";
  resumed.out = dir_.path() / "resumed";
  resumed.restart = dir_.path() / "first" / "restart.h5";
  resumed.progress = false;
  nlohmann::json longer = common::load_json_file(resumed.scene);
  longer["time"]["end"] = 2 * kSteps * 1e-4;
  dir_.write("first.json", longer.dump());
  run_scene(resumed);
  try {
    audit("resumed");
    FAIL() << "audited a resumed run";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("resumed from a restart"), std::string::npos) << e.what();
  }

  // More audited points than the scene has.
  try {
    run(library_material("live"), 9, "too_many");
    FAIL() << "audited 9 of 8 points";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/audit/points: expected 1 to 8 points"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace grainbank::mpm::app
