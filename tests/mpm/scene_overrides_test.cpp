// `--law`, `--library` and `--material` rewrite the DEM-backed materials of a scene (and only those)
// at the JSON level, `--set` any key; bad values are refused naming the flag and what was expected;
// the binary runs a live scene with `--law live` and keeps the rewritten scene in its output folder,
// and `mpm_solver scene` writes a variant without running it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "common/json_input.hpp"
#include "common/temporary_directory.hpp"
#include "mpm_solver/app/scene_overrides.hpp"
#include "mpm_solver/laws/law_registry.hpp"

namespace grainbank::mpm::app {
namespace {

namespace fs = std::filesystem;

const nlohmann::json kScene = nlohmann::json::parse(R"({
  "materials": [
    {"name": "rock", "law": "elastic", "density": 2000, "young": 1e6, "poisson": 0.3},
    {"name": "snow", "law": "live", "cell": "cells/snow.json", "q_h": 0.01},
    {"name": "firn", "law": "hybrid", "library": "lib", "template": 2}
  ]
})");

SceneOverrides overrides(std::optional<std::string> law, std::optional<fs::path> library,
                         std::optional<nlohmann::json> material = std::nullopt, std::vector<SceneSetting> settings = {}) {
  SceneOverrides o;
  o.law = std::move(law);
  o.library = std::move(library);
  o.material = std::move(material);
  o.settings = std::move(settings);
  return o;
}

std::string error_of(const nlohmann::json& scene, const SceneOverrides& o) {
  try {
    apply_overrides(scene, "/scenes", o);
  } catch (const common::InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(SceneOverrides, LawReplacesTheLawOfDemBackedMaterialsOnly) {
  const nlohmann::json out = apply_overrides(kScene, "/scenes", overrides("cache", std::nullopt));
  EXPECT_EQ(out["materials"][0], kScene["materials"][0]);  // analytic: untouched
  EXPECT_EQ(out["materials"][1]["law"], "cache");
  EXPECT_EQ(out["materials"][2]["law"], "cache");
  // Relative paths now absolute, from the scene's folder; the other keys are kept.
  EXPECT_EQ(out["materials"][1]["cell"], "/scenes/cells/snow.json");
  EXPECT_EQ(out["materials"][2]["library"], "/scenes/lib");
  EXPECT_EQ(out["materials"][1]["q_h"], 0.01);
  EXPECT_EQ(out["materials"][2]["template"], 2);
}

TEST(SceneOverrides, LawDropsTheKeysTheNewLawDoesNotTake) {
  nlohmann::json scene = kScene;
  scene["materials"][2]["lookup"] = {{"k", 4}};
  scene["materials"][2]["fallback"] = {{"return_after", 5}};
  scene["materials"][2]["enrich"] = true;
  scene["materials"][2]["cell"] = "cells/firn.json";  // a check of the library's material
  const nlohmann::json live = apply_overrides(scene, "/scenes", overrides("live", std::nullopt));
  EXPECT_EQ(live["materials"][2], nlohmann::json::parse(R"({"name": "firn", "law": "live", "library": "/scenes/lib",
                                                            "template": 2})"));
  // cache keeps its lookup and drops what only hybrid takes.
  const nlohmann::json cache = apply_overrides(scene, "/scenes", overrides("cache", std::nullopt));
  EXPECT_EQ(cache["materials"][2]["lookup"], scene["materials"][2]["lookup"]);
  EXPECT_FALSE(cache["materials"][2].contains("fallback"));
  EXPECT_FALSE(cache["materials"][2].contains("enrich"));
  EXPECT_EQ(cache["materials"][2]["cell"], "/scenes/cells/firn.json");
}

// A block both laws take (a fallback) keeps only the keys the new law takes in it.
TEST(SceneOverrides, LawDropsTheKeysOfABlockTheNewLawDoesNotTake) {
  nlohmann::json scene = kScene;
  scene["materials"][2] = nlohmann::json::parse(R"({"name": "firn", "law": "surrogate", "library": "lib",
      "template": 2, "tolerance": 50, "fallback": {"return_after": 5, "warm_start": "state",
      "stress_tolerance": 100, "catch_up_strain_per_step": 1e-5}})");
  const nlohmann::json hybrid = apply_overrides(scene, "/scenes", overrides("hybrid", std::nullopt));
  EXPECT_EQ(hybrid["materials"][2]["fallback"], nlohmann::json::parse(R"({"return_after": 5})"));
  EXPECT_FALSE(hybrid["materials"][2].contains("tolerance"));
  // And back: the hybrid's fallback start is not the surrogate's.
  nlohmann::json started = hybrid;
  started["materials"][2]["fallback"]["start"] = "replay";
  const nlohmann::json back = apply_overrides(started, "/scenes", overrides("surrogate", std::nullopt));
  EXPECT_EQ(back["materials"][2]["fallback"], nlohmann::json::parse(R"({"return_after": 5})"));
}

TEST(SceneOverrides, LibraryReplacesTheCellSourceOfDemBackedMaterials) {
  const nlohmann::json out = apply_overrides(kScene, "/scenes", overrides(std::nullopt, "/data/LIB"));
  EXPECT_EQ(out["materials"][0], kScene["materials"][0]);
  EXPECT_FALSE(out["materials"][1].contains("cell"));
  EXPECT_EQ(out["materials"][1]["library"], "/data/LIB");
  EXPECT_EQ(out["materials"][1]["law"], "live");
  EXPECT_EQ(out["materials"][1]["template"], 1);  // the cell's material named none: the library's first
  EXPECT_EQ(out["materials"][2]["library"], "/data/LIB");
  EXPECT_EQ(out["materials"][2]["template"], 2);
  // A relative --library is relative to the working directory, like any command-line path.
  const nlohmann::json rel = apply_overrides(kScene, "/scenes", overrides(std::nullopt, "LIB"));
  EXPECT_EQ(rel["materials"][1]["library"], (fs::current_path() / "LIB").lexically_normal().string());
}

TEST(SceneOverrides, ErrorsNameTheFlagAndTheExpectedValue) {
  // The DEM-backed laws are whatever is registered (laws/law_registry.hpp).
  EXPECT_EQ(error_of(kScene, overrides("elastic", std::nullopt)),
            "--law: expected " + dem_backed_law_names() + ", got \"elastic\"");
  EXPECT_EQ(error_of(kScene, overrides(std::nullopt, "")),
            "--library: expected a library directory, got an empty path");
  nlohmann::json analytic = kScene;
  analytic["materials"] = nlohmann::json::array({kScene["materials"][0]});
  EXPECT_EQ(error_of(analytic, overrides(std::nullopt, "LIB")),
            "--library: expected a scene with a DEM-backed material (law " + dem_backed_law_names() + "), found none");
  EXPECT_EQ(error_of(analytic, overrides("live", "LIB")),
            "--law/--library: expected a scene with a DEM-backed material (law " + dem_backed_law_names() + "), found none");
}

TEST(SceneOverrides, MaterialPatchMergesIntoDemBackedMaterialsAfterTheLaw) {
  nlohmann::json scene = kScene;
  scene["materials"][2]["lookup"] = {{"k", 4}, {"tolerance", 0.5}};
  const SceneOverrides o =
      overrides("hybrid", std::nullopt, parse_material_patch(R"({"lookup": {"tolerance": 10}, "q_h": null})"));
  const nlohmann::json out = apply_overrides(scene, "/scenes", o);
  EXPECT_EQ(out["materials"][0], kScene["materials"][0]);
  // RFC 7396: objects merge key by key, null removes.
  EXPECT_EQ(out["materials"][2]["lookup"], nlohmann::json::parse(R"({"k": 4, "tolerance": 10})"));
  EXPECT_EQ(out["materials"][1]["lookup"], nlohmann::json::parse(R"({"tolerance": 10})"));
  EXPECT_FALSE(out["materials"][1].contains("q_h"));
  EXPECT_EQ(out["materials"][1]["law"], "hybrid");
}

// A key the law does not take is refused when the variant is written, not when it is run.
TEST(SceneOverrides, MaterialPatchWithAKeyItsLawDoesNotTakeIsRefused) {
  const std::string error =
      error_of(kScene, overrides("live", std::nullopt, parse_material_patch(R"({"error_budget": 300})")));
  EXPECT_EQ(error.rfind("--material: key \"error_budget\" is not a key of law \"live\" (expected one of ", 0), 0u)
      << error;
  // The surrogate takes it.
  EXPECT_NO_THROW(apply_overrides(kScene, "/scenes",
                                  overrides("surrogate", std::nullopt, parse_material_patch(R"({"error_budget": 300})"))));
  // A key of a block is checked against the block's keys of the law, and named with its block.
  const std::string nested = error_of(
      kScene, overrides("surrogate", std::nullopt, parse_material_patch(R"({"fallback": {"start": "replay"}})")));
  EXPECT_EQ(nested.rfind("--material: key \"fallback.start\" is not a key of law \"surrogate\" (expected one of "
                         "return_after, warm_start, ",
                         0),
            0u)
      << nested;
  EXPECT_NO_THROW(apply_overrides(
      kScene, "/scenes", overrides("hybrid", std::nullopt, parse_material_patch(R"({"fallback": {"start": "replay"}})"))));
}

TEST(SceneOverrides, MaterialPatchWithACellReplacesTheLibrary) {
  const SceneOverrides o = overrides("live", "/data/LIB", nlohmann::json{{"cell", "/cells/c64.json"}});
  const nlohmann::json out = apply_overrides(kScene, "/scenes", o);
  EXPECT_EQ(out["materials"][2],
            nlohmann::json::parse(R"({"name": "firn", "law": "live", "cell": "/cells/c64.json"})"));
  // A relative cell of the patch is relative to the working directory.
  const nlohmann::json rel =
      apply_overrides(kScene, "/scenes", overrides(std::nullopt, std::nullopt, nlohmann::json{{"cell", "c.json"}}));
  EXPECT_EQ(rel["materials"][1]["cell"], (fs::current_path() / "c.json").lexically_normal().string());
}

TEST(SceneOverrides, SettingsSetKeysOfAnySceneInOrder) {
  nlohmann::json analytic = kScene;
  analytic["materials"] = nlohmann::json::array({kScene["materials"][0]});
  analytic["regions"] = nlohmann::json::parse(R"([{"material": "rock", "points_per_cell": 2}])");
  const SceneOverrides o = overrides(std::nullopt, std::nullopt, std::nullopt,
                                     {parse_setting("/time/end=0.05"), parse_setting("/grid/cells=[8, 4]"),
                                      parse_setting("/regions/0/points_per_cell=1"), parse_setting("/time/end=0.1")});
  const nlohmann::json out = apply_overrides(analytic, "/scenes", o);
  EXPECT_EQ(out["time"], nlohmann::json::parse(R"({"end": 0.1})"));
  EXPECT_EQ(out["grid"]["cells"], nlohmann::json::parse("[8, 4]"));
  EXPECT_EQ(out["regions"][0]["points_per_cell"], 1);
  EXPECT_EQ(out["materials"], analytic["materials"]);
}

TEST(SceneOverrides, MaterialAndSettingErrorsNameTheFlag) {
  EXPECT_THROW(parse_material_patch("[1]"), common::InputError);
  EXPECT_THROW(parse_material_patch("{lookup"), common::InputError);
  EXPECT_THROW(parse_setting("time/end=1"), common::InputError);
  EXPECT_THROW(parse_setting("/time/end"), common::InputError);
  try {
    parse_setting("/law=hybrid");
    FAIL() << "an unquoted string was taken";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the value is not JSON (a string needs quotes)"), std::string::npos)
        << e.what();
  }
  nlohmann::json analytic = kScene;
  analytic["materials"] = nlohmann::json::array({kScene["materials"][0]});
  EXPECT_EQ(error_of(analytic, overrides(std::nullopt, std::nullopt, nlohmann::json::object())),
            "--material: expected a scene with a DEM-backed material (law " + dem_backed_law_names() + "), found none");
  EXPECT_EQ(error_of(kScene, overrides(std::nullopt, std::nullopt, std::nullopt, {parse_setting("/materials/3/q_h=1")})),
            "--set /materials/3/q_h: expected an index below 3, got \"3\"");
  EXPECT_EQ(error_of(kScene, overrides(std::nullopt, std::nullopt, std::nullopt, {parse_setting("/materials/x=1")})),
            "--set /materials/x: expected an index below 3 (or - to append), got \"x\"");
}

// A two-point live scene with a small cell, one point tracked.
void write_live_scene(const TemporaryDirectory& dir) {
  fs::create_directories(dir.path() / "cells");
  dir.write("cells/cell.json", R"({
    "material": {"density": 920, "k_n": 2000, "k_t": 600, "restitution": 0.3, "friction": 0.2, "contact_weight": 0.5,
                 "bond": {"tensile_strength": 8e-4, "shear_strength": 9.6e-4, "exponent": 2, "bonding_distance": 0.05}},
    "effects": {"cohesion": true, "kinetic_stress": false, "rolling_resistance": false},
    "preparation": {"spheres": 20, "diameter": {"min": 3.4e-4, "max": 4.0e-4}, "pressure": 1000, "seed": 3,
                    "inertial_number": 0.01}
  })");
  dir.write("scene.json", R"({
    "grid": {"origin": [0, 0], "cell_size": 0.1, "cells": [6, 6]},
    "time": {"end": 2e-4, "output_interval": 1e-4, "max_time_step": 1e-4},
    "materials": [{"name": "snow", "law": "live", "cell": "cells/cell.json"}],
    "regions": [{"material": "snow", "rectangle": {"min": [0.2, 0.2], "max": [0.4, 0.3]}, "points_per_cell": 1,
                 "velocity": [0.1, 0]}],
    "tracked_points": [[0.25, 0.25]]
  })");
}

std::string first_line(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  return line;
}

TEST(SceneOverrides, CommandLineRunsTheRewrittenSceneAndWritesTrackedCells) {
  const TemporaryDirectory dir("gb_mpm_overrides");
  write_live_scene(dir);
  const fs::path out = dir.path() / "out";
  // Run from another working directory: the rewritten scene must find the cell by absolute path.
  const std::string cmd = "cd / && " + std::string(MPM_SOLVER_BINARY) + " " + (dir.path() / "scene.json").string() +
                          " --law live --out " + out.string() + " --json > " + (dir.path() / "stdout.json").string();
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const nlohmann::json rewritten = common::load_json_file(out / "scene" / "scene.json");
  EXPECT_EQ(rewritten["materials"][0]["cell"], (dir.path() / "cells" / "cell.json").string());
  // The tracked live point's cell at each of the 3 output steps: packing CSV and VTK.
  for (const char* step : {"000000", "000001", "000002"})
    for (const char* ext : {".csv", ".vtk"}) {
      const fs::path cell = out / "cells" / (std::string("point_0_") + step + ext);
      EXPECT_TRUE(fs::exists(cell)) << cell;
    }

  const std::string bad = std::string(MPM_SOLVER_BINARY) + " " + (dir.path() / "scene.json").string() +
                          " --law plastic --out " + out.string() + " 2> " + (dir.path() / "stderr.txt").string();
  EXPECT_NE(std::system(bad.c_str()), 0);
  EXPECT_EQ(first_line(dir.path() / "stderr.txt"),
            "mpm_solver: --law: expected " + dem_backed_law_names() + ", got \"plastic\"");
  // A library that does not exist: the loader's error, with the rewritten scene named.
  const std::string missing = std::string(MPM_SOLVER_BINARY) + " " + (dir.path() / "scene.json").string() +
                              " --library " + (dir.path() / "nolib").string() + " --out " + out.string() + " 2> " +
                              (dir.path() / "stderr.txt").string();
  EXPECT_NE(std::system(missing.c_str()), 0);
  const std::string line = first_line(dir.path() / "stderr.txt");
  EXPECT_EQ(line.rfind("mpm_solver: scene.json: /materials/0", 0), 0u) << line;
  EXPECT_NE(line.find("as rewritten by the command line: " + (out / "scene" / "scene.json").string()),
            std::string::npos)
      << line;
}

TEST(SceneOverrides, SceneCommandWritesTheVariantWithoutRunning) {
  const TemporaryDirectory dir("gb_mpm_scene_command");
  write_live_scene(dir);
  const fs::path variant = dir.path() / "variants" / "short.json";
  const std::string cmd = "cd / && " + std::string(MPM_SOLVER_BINARY) + " scene " +
                          (dir.path() / "scene.json").string() + R"( --law hybrid --material '{"lookup": {"k": 1}}')" +
                          " --set /time/end=1e-4 --set '/tracked_points=[]' --out " + variant.string();
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  nlohmann::json expected = common::load_json_file(dir.path() / "scene.json");
  expected["materials"][0] = {{"name", "snow"},
                              {"law", "hybrid"},
                              {"cell", (dir.path() / "cells" / "cell.json").string()},
                              {"lookup", {{"k", 1}}}};
  expected["time"]["end"] = 1e-4;
  expected["tracked_points"] = nlohmann::json::array();
  EXPECT_EQ(common::load_json_file(variant), expected);
  EXPECT_FALSE(fs::exists(dir.path() / "variants" / "points.pvd"));

  const std::string bad = std::string(MPM_SOLVER_BINARY) + " scene " + (dir.path() / "scene.json").string() +
                          " --set /time/end --out " + variant.string() + " 2> " + (dir.path() / "stderr.txt").string();
  EXPECT_NE(std::system(bad.c_str()), 0);
  EXPECT_EQ(first_line(dir.path() / "stderr.txt").rfind("mpm_solver: --set: expected /json/pointer=JSON value", 0), 0u);
}

}  // namespace
}  // namespace grainbank::mpm::app
