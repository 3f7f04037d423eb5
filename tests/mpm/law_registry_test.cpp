// The law registry: a law defined in one file (here, this test file) is a scene material with its
// own keys, its own state in restart files and its entry in `mpm_solver laws`, with nothing else in
// the tree touched. The law below is a Newtonian fluid σ = 2η D that also integrates its dissipated
// work w = ∫ σ:D dt per point; in simple shear at rate γ̇, σ_xy = η γ̇ and w(t) = η γ̇² t exactly.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "mpm_solver/app/laws_command.hpp"
#include "common/json_input.hpp"
#include "common/temporary_directory.hpp"
#include "mpm_solver/io/restart.hpp"
#include "mpm_solver/io/scene_input.hpp"
#include "mpm_solver/laws/law_registry.hpp"

namespace grainbank::mpm {
namespace {

class ViscousFluid : public ConstitutiveLaw {
 public:
  ViscousFluid(double density, double viscosity) : density_(density), viscosity_(viscosity) {}
  std::string name() const override { return "test_viscous_fluid"; }
  double density() const override { return density_; }
  std::size_t add_point(PointStress& initial_stress) override {
    initial_stress = PointStress{};
    work_.push_back(0);
    return work_.size() - 1;
  }
  void update(std::size_t slot, const KinematicIncrement& increment, const Mat2&, PointStress& stress) override {
    const Mat2 D = 0.5 * (increment.L + increment.L.transpose());
    stress.in_plane = 2 * viscosity_ * D;
    stress.zz = 0;
    work_[slot] += (stress.in_plane.array() * D.array()).sum() * increment.dt;
  }
  double p_wave_modulus(std::size_t) const override { return 1e6; }
  void save_state(LawStateWriter& out) const override { out.write_table("work", work_, 1); }
  void restore_state(LawStateReader& in) override { work_ = in.read_table("work", 1); }
  double work(std::size_t slot) const { return work_[slot]; }

 private:
  double density_, viscosity_;
  std::vector<double> work_;
};

constexpr std::string_view kKeys[] = {"name", "law", "density", "viscosity"};

std::unique_ptr<ConstitutiveLaw> read(const common::JsonNode& material, const LawContext&) {
  return std::make_unique<ViscousFluid>(material.number("density", common::Range::positive()),
                                        material.number("viscosity", common::Range::positive()));
}

const LawRegistration registration{{"test_viscous_fluid", kKeys, false, &read}};

constexpr double kShearRate = 2.0, kViscosity = 3.0, kDt = 1e-4;

std::string scene(const std::string& material_extra = "") {
  return R"({
  "grid": {"cell_size": 0.1, "cells": [10, 10]},
  "time": {"end": 0.01, "output_interval": 0.01},
  "integration": {"homogeneous_drive": {"L": [[0, )" + std::to_string(kShearRate) + R"(], [0, 0]], "origin": [0.5, 0.5]}},
  "materials": [{"name": "fluid", "law": "test_viscous_fluid", "density": 1000, "viscosity": )" +
         std::to_string(kViscosity) + material_extra + R"(}],
  "regions": [{"material": "fluid", "rectangle": {"min": [0.4, 0.4], "max": [0.6, 0.6]}}]
})";
}

std::filesystem::path write(const TemporaryDirectory& dir, const std::string& text) {
  const std::filesystem::path file = dir.path() / "scene.json";
  std::ofstream(file) << text;
  return file;
}

const ViscousFluid& fluid(const Solver& solver) { return dynamic_cast<const ViscousFluid&>(solver.law(0)); }

TEST(LawRegistry, ALawFromItsOwnFileIsASceneMaterialWithItsAnalyticResponse) {
  const TemporaryDirectory dir("gb_law_registry");
  const io::Scene s = io::load_scene(write(dir, scene()));
  for (int k = 0; k < 50; ++k) s.solver->step(kDt);
  for (const MaterialPoint& mp : s.solver->points()) {
    EXPECT_NEAR(mp.stress.in_plane(0, 1), kViscosity * kShearRate, 1e-9 * kViscosity * kShearRate);
    EXPECT_NEAR(fluid(*s.solver).work(mp.slot), kViscosity * kShearRate * kShearRate * s.solver->time(), 1e-9);
  }
}

TEST(LawRegistry, TheLawsOwnStateSurvivesARestartExactly) {
  const TemporaryDirectory dir("gb_law_registry");
  const std::filesystem::path file = write(dir, scene());
  const io::Scene straight = io::load_scene(file), first = io::load_scene(file), resumed = io::load_scene(file);
  for (int k = 0; k < 40; ++k) straight.solver->step(kDt);
  for (int k = 0; k < 25; ++k) first.solver->step(kDt);
  io::write_restart(dir.path() / "restart.h5", *first.solver);
  io::read_restart(dir.path() / "restart.h5", *resumed.solver);
  for (int k = 25; k < 40; ++k) resumed.solver->step(kDt);
  ASSERT_EQ(resumed.solver->points().size(), straight.solver->points().size());
  for (const MaterialPoint& mp : straight.solver->points()) {
    EXPECT_EQ(fluid(*resumed.solver).work(mp.slot), fluid(*straight.solver).work(mp.slot));
    EXPECT_NEAR(fluid(*straight.solver).work(mp.slot), kViscosity * kShearRate * kShearRate * 40 * kDt, 1e-9);
  }
}

TEST(LawRegistry, ALawAcceptsExactlyTheKeysItPublishes) {
  const TemporaryDirectory dir("gb_law_registry");
  try {
    io::load_scene(write(dir, scene(", \"young\": 1e6")));
    FAIL() << "an unknown key was accepted";
  } catch (const common::InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "scene.json: /materials/0/young: unknown key; allowed keys here: name, law, density, viscosity");
  }
  const nlohmann::json catalogue = app::law_catalogue();
  ASSERT_TRUE(catalogue["laws"].contains("test_viscous_fluid"));
  EXPECT_EQ(catalogue["laws"]["test_viscous_fluid"]["keys"],
            nlohmann::json::array({"name", "law", "density", "viscosity"}));
  EXPECT_FALSE(catalogue["laws"]["test_viscous_fluid"]["dem_backed"].get<bool>());
  for (const char* law : {"elastic", "drucker_prager", "live", "cache", "hybrid"})
    EXPECT_TRUE(catalogue["laws"].contains(law)) << law << " is not registered";
  // A block whose keys depend on the law is published with them.
  EXPECT_EQ(catalogue["laws"]["test_viscous_fluid"]["blocks"], nlohmann::json::object());
  EXPECT_EQ(catalogue["laws"]["hybrid"]["blocks"]["fallback"],
            nlohmann::json::array({"start", "max_drive_strain", "return_after"}));
}

TEST(LawRegistry, ANameIsRegisteredOnce) {
  EXPECT_THROW(LawRegistration({"test_viscous_fluid", kKeys, false, &read}), std::logic_error);
}

}  // namespace
}  // namespace grainbank::mpm
