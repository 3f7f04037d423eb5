// The live MPM×DEM law: points of a homogeneously sheared block each drive their own DEM cell; the
// stress, σ_zz and volume of a point equal those of a stand-alone dem::DemCell (a copy of the same
// template) driven by the same increments, embedded in 3D as plane strain, to round-off. Also:
// every point owns a distinct cell, and seed Eq. 4 limits the step, seeing the packing (not how
// re-tiling and flips describe it) and only while its grains touch.
#include <gtest/gtest.h>

#include <cmath>

#include "dem_sampler/cell/preparation.hpp"
#include "dem_sampler/cell/retiling.hpp"
#include "dem_sampler/cell/snow_preset.hpp"
#include "mpm_solver/dem_laws/dem_material_input.hpp"
#include "mpm_solver/dem_laws/live_dem_law.hpp"
#include "tests/mpm/mpm_test_util.hpp"

namespace grainbank::mpm {
namespace {

dem::DemCell small_cohesive_cell() { return dem::prepare_cell(dem::snow_material(), dem::snow_preparation(30, 5)); }

TEST(LiveLaw, PointsReproduceStandAloneCellsDrivenByTheSameIncrements) {
  const dem::DemCell cell_template = small_cohesive_cell();
  LiveDemSettings settings;
  settings.substepping = {0.1, 1, 0.2};
  SolverSettings solver_settings;
  solver_settings.transfer = testing::pure_pic();
  Solver solver(Grid(Vec2(0, 0), 0.1, 6, 6), solver_settings);
  solver.add_law(std::make_unique<LiveDemLaw>(cell_template, settings));
  // 6 × 6 points (2 per cell) in simple shear v_x = γ̇ (y - y_c), plus a little stretching.
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) {
      const Vec2 x(0.225 + 0.05 * i, 0.225 + 0.05 * j);
      solver.add_point(0, x, 0.0025, 0.025, Vec2(2.0 * (x.y() - 0.35) + 0.5 * (x.x() - 0.35), 0));
    }
  const auto& law = dynamic_cast<const LiveDemLaw&>(solver.law(0));
  const double v0 = law.cell(0).volume();
  std::vector<dem::DemCell> reference;
  for (std::size_t k = 0; k < solver.points().size(); ++k) reference.emplace_back(cell_template);

  const double dt = 2e-4;
  double max_shear_rate = 0;
  for (int step = 0; step < 8; ++step) {
    solver.step(dt);
    for (const MaterialPoint& mp : solver.points()) {
      max_shear_rate = std::max(max_shear_rate, std::abs(mp.velocity_gradient(0, 1)));
      dem::DemCell& ref = reference[mp.slot];
      const Mat2 increment = KinematicIncrement::of_velocity_gradient(mp.velocity_gradient, dt).F;
      const dem::Mat3 s = ref.advance(embed_plane_strain(increment), dt, settings.substepping).stress;
      const double scale = std::abs(s.trace());
      EXPECT_NEAR(mp.stress.in_plane(0, 0), s(0, 0), 1e-12 * scale);
      EXPECT_NEAR(mp.stress.in_plane(1, 1), s(1, 1), 1e-12 * scale);
      EXPECT_NEAR(mp.stress.in_plane(0, 1), 0.5 * (s(0, 1) + s(1, 0)), 1e-12 * scale);
      EXPECT_NEAR(mp.stress.zz, s(2, 2), 1e-12 * scale);
      EXPECT_NEAR(mp.volume, mp.initial_volume * ref.volume() / v0, 1e-12 * mp.volume);
      EXPECT_EQ(law.damage(mp.slot), ref.measures().damage);
    }
  }
  // The increments were not trivial, and differ from point to point (no shared cell).
  std::printf("largest shear rate L_xy seen: %g 1/s\n", max_shear_rate);
  EXPECT_GT(max_shear_rate, 0.5);
  const MaterialPoint& a = solver.points().front();
  double spread = 0;
  for (const MaterialPoint& mp : solver.points()) spread = std::max(spread, (mp.stress.in_plane - a.stress.in_plane).norm());
  EXPECT_GT(spread, 0);
  for (std::size_t k = 1; k < solver.points().size(); ++k) EXPECT_NE(&law.cell(k), &law.cell(0));
}

TEST(LiveLaw, SeedEquation4LimitsTheStep) {
  const dem::DemCell cell_template = small_cohesive_cell();
  LiveDemSettings settings;
  settings.q_h = 0.02;
  LiveDemLaw law(cell_template, settings);
  PointStress s;
  law.add_point(s);
  EXPECT_LT(pressure_of(s), 0.0 + 2000);  // prepared near p_0 = 1000 Pa
  EXPECT_GT(pressure_of(s), 500);
  Mat2 L;
  L << 0, 3, 0, 0;  // ḣ = L h: only the x row moves, by 3 h_yj
  const dem::Mat3 h = law.cell(0).cell_matrix();
  const double rate = 3 * h.row(1).cwiseAbs().maxCoeff();
  double d_min = 1;
  for (double r : cell_template.radii()) d_min = std::min(d_min, 2 * r);
  EXPECT_NEAR(law.time_step_limit(0, Mat2::Identity(), L), 0.02 * d_min / rate, 1e-15);
  EXPECT_TRUE(std::isinf(law.time_step_limit(0, Mat2::Identity(), Mat2::Zero())));
  EXPECT_GT(law.p_wave_modulus(0), 0);
}

// Re-tiling and basis flips describe the same packing differently; seed Eq. 4 must see the packing.
TEST(LiveLaw, SeedEquation4IsBlindToRetilingAndFlips) {
  const dem::DemCell cell_template = small_cohesive_cell();
  const dem::Mat3 h0 = cell_template.cell_matrix();
  ASSERT_TRUE(h0.isDiagonal()) << "the flip check below assumes an orthorhombic template";
  LiveDemSettings settings;
  settings.q_h = 0.02;
  const LiveCellModel model(cell_template, settings);
  dem::DemCell cell = model.new_cell();
  cell.step_with_velocity_gradient(dem::Mat3::Zero(), 1e-9);  // measures its contacts
  Mat2 L;
  L << 0, 3, 0, 0;  // simple shear: the x row of ḣ = L h is 3 h_yj
  const double limit = model.time_step_limit(cell, L);
  double d_min = 1;
  for (double r : cell_template.radii()) d_min = std::min(d_min, 2 * r);
  EXPECT_NEAR(limit, 0.02 * d_min / (3 * h0.row(1).cwiseAbs().maxCoeff()), 1e-12 * limit);

  // Doubled along y, the cell's own x-velocity doubles; the packing deforms no faster.
  const dem::DemCell doubled = model.cell_from(dem::doubled_along(cell.state(), 1));
  ASSERT_EQ(doubled.size(), 2 * cell.size());
  EXPECT_NEAR(doubled.cell_matrix().row(1).cwiseAbs().maxCoeff(), 2 * h0.row(1).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(model.time_step_limit(doubled, L), limit, 1e-12 * limit);

  // A point without a cell: the template deformed by F. Sheared by γ = 5, the lattice is the
  // template's again (a flip undoes an integer shear of an orthorhombic cell), while the x row of
  // the unflipped cell F h0, read by L' = (v_y = 3 x), would reach 5 h0_yy.
  ASSERT_GT(5 * h0(1, 1), h0(0, 0)) << "else the unflipped cell would be no faster";
  Mat2 sheared, L_prime;
  sheared << 1, 5, 0, 1;
  L_prime << 0, 0, 3, 0;
  EXPECT_NEAR(model.time_step_limit(Mat2::Identity(), L), limit, 1e-12 * limit);
  const double unsheared = model.time_step_limit(Mat2::Identity(), L_prime);
  EXPECT_NEAR(model.time_step_limit(sheared, L_prime), unsheared, 1e-12 * unsheared);
  EXPECT_NEAR(unsheared, 0.02 * d_min / (3 * h0(0, 0)), 1e-12 * unsheared);
}

// A cell whose grains all fly apart has no contact or bond for the step to resolve.
TEST(LiveLaw, SeedEquation4SetsNoLimitOnACellInFreeFlight) {
  const dem::DemCell cell_template = small_cohesive_cell();
  const LiveCellModel model(cell_template, LiveDemSettings{});
  dem::CellState spread = cell_template.state();
  spread.h *= 3;  // same reduced positions: every gap triples, F = 3 I
  for (dem::Bond& b : spread.bonds) b.integrity = 0;
  dem::DemCell flying = model.cell_from(spread);
  flying.step_with_velocity_gradient(dem::Mat3::Zero(), 1e-9);
  ASSERT_EQ(flying.contact_count(), 0u);
  Mat2 L;
  L << 50, 0, 0, 50;
  EXPECT_EQ(flying.interacting_pairs(), 0);
  EXPECT_TRUE(std::isinf(model.time_step_limit(flying, L)));
  // The same deformation with grains in contact is limited.
  EXPECT_TRUE(std::isfinite(model.time_step_limit(3 * Mat2::Identity(), L)));
  dem::DemCell touching = model.new_cell();
  touching.step_with_velocity_gradient(dem::Mat3::Zero(), 1e-9);
  EXPECT_GT(touching.interacting_pairs(), 0);
  EXPECT_TRUE(std::isfinite(model.time_step_limit(touching, L)));
}

// A cell whose grains flew apart far beyond its packing holds while its point dilates, and follows
// again when the point is compressed; a cell not yet that dilute follows every increment.
TEST(LiveLaw, ADispersedCellTakesNoDilation) {
  const dem::DemCell cell_template = small_cohesive_cell();
  LiveDemSettings settings;
  settings.substepping = {0.1, 1, 0.2};
  const LiveCellModel model(cell_template, settings);
  const auto spread_by = [&](double stretch) {
    dem::CellState spread = cell_template.state();
    spread.h.topRows<2>() *= stretch;  // in-plane, same reduced positions: F grows by stretch²
    for (dem::Bond& b : spread.bonds) b.integrity = 0;
    dem::DemCell cell = model.cell_from(spread);
    cell.step_with_velocity_gradient(dem::Mat3::Zero(), 1e-9);
    return cell;
  };
  const auto increment = [](double stretch) {
    return KinematicIncrement::of_deformation(stretch * Mat2::Identity(), 1e-4);
  };
  CouplingCounters counters;
  dem::DemCell dispersed = spread_by(12);
  ASSERT_EQ(dispersed.interacting_pairs(), 0);
  ASSERT_NEAR(model.volume_ratio(dispersed), 144, 1e-9);
  const dem::Mat3 h = dispersed.cell_matrix();
  const dem::Mat3 stress = model.advance(dispersed, increment(1.1), counters);
  EXPECT_EQ(stress, dem::Mat3::Zero());
  EXPECT_EQ(dispersed.cell_matrix(), h) << "a dilating increment must leave the dispersed cell as it is";
  EXPECT_EQ(counters.dispersed_holds, 1u);
  model.advance(dispersed, increment(0.9), counters);
  EXPECT_NEAR(model.volume_ratio(dispersed), 144 * 0.81, 1e-9) << "compression is followed";
  EXPECT_EQ(counters.dispersed_holds, 1u);

  dem::DemCell dilute = spread_by(3);
  ASSERT_EQ(dilute.interacting_pairs(), 0);
  model.advance(dilute, increment(1.1), counters);
  EXPECT_NEAR(model.volume_ratio(dilute), 9 * 1.21, 1e-9) << "below the threshold every increment is followed";
  EXPECT_EQ(counters.dispersed_holds, 1u);
}

TEST(LiveLaw, RetilingCapIsReadAndBadKeysAreNamed) {
  const nlohmann::json material = {{"retiling", {{"max_spheres", 240}}}};
  EXPECT_EQ(read_live_settings(common::JsonNode(material, "scene.json", "/materials/0")).max_spheres, 240u);
  EXPECT_EQ(read_live_settings(common::JsonNode(nlohmann::json::object(), "scene.json", "/materials/0")).max_spheres, 0u)
      << "off unless asked for";
  const nlohmann::json bad = {{"retiling", {{"cap", 240}}}};
  try {
    read_live_settings(common::JsonNode(bad, "scene.json", "/materials/0"));
    FAIL() << "an unknown key was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("scene.json: /materials/0/retiling/cap: unknown key; allowed keys here: max_spheres"),
              std::string::npos)
        << e.what();
  }
  const nlohmann::json regenerate = {{"retiling", {{"max_spheres", 240}, {"beyond_cap", "regenerate"}}}};
  EXPECT_TRUE(read_live_settings(common::JsonNode(regenerate, "scene.json", "/materials/0")).regenerate_beyond_cap);
  EXPECT_FALSE(read_live_settings(common::JsonNode(material, "scene.json", "/materials/0")).regenerate_beyond_cap)
      << "past the cap the run stops unless asked otherwise";
  const auto message = [](const nlohmann::json& m) {
    try {
      read_live_settings(common::JsonNode(m, "scene.json", "/materials/0"));
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message({{"retiling", {{"max_spheres", 240}, {"beyond_cap", "restart"}}}})
                .find("/materials/0/retiling/beyond_cap: expected \"stop\" or \"regenerate\""),
            std::string::npos);
  EXPECT_NE(message({{"retiling", {{"beyond_cap", "regenerate"}}}}).find("needs a \"max_spheres\" cap"),
            std::string::npos);
}

}  // namespace
}  // namespace grainbank::mpm
