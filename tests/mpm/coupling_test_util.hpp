// Helpers of the cache/hybrid tests: a small cohesive template stored in a fresh library, the
// library-backed laws built on it, and a homogeneously deformed block of points.
#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <limits>
#include <memory>
#include <string>

#include "dem_sampler/cell/preparation.hpp"
#include "dem_sampler/cell/snow_preset.hpp"
#include "mpm_solver/dem_laws/live_dem_law.hpp"
#include "mpm_solver/core/solver.hpp"
#include "mpm_solver/dem_laws/library_law.hpp"
#include "mpm_solver/io/coupling_report.hpp"
#include "database/store/library.hpp"

namespace grainbank::mpm::testing {

inline const dem::DemCell& small_snow_cell() {
  static const dem::DemCell cell = dem::prepare_cell(dem::snow_material(), dem::snow_preparation(20, 9));
  return cell;
}

// A fresh directory for a library named after the running test.
inline std::filesystem::path fresh_library_dir(const std::string& suffix = "") {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) /
                                    ("gb_" + std::string(info->test_suite_name()) + "_" + info->name() + suffix);
  std::filesystem::remove_all(dir);
  return dir;
}

// Creates a library in `dir` holding `cell` as its only template; returns the template id.
inline std::int64_t create_library(const std::filesystem::path& dir, const dem::DemCell& cell) {
  db::Library library = db::Library::create(dir, cell.material());
  db::ShardWriter writer(library, "templates");
  return writer.add_template(cell.material(), {{"test", true}}, {cell.state(), cell.skin()});
}

inline LibraryLawSettings coupling_settings(Fallback fallback, bool enrich) {
  LibraryLawSettings s;
  s.fallback = fallback;
  s.enrich = enrich;
  s.snapshot_interval = 4;
  s.live.substepping = {0.1, 1, 0.2};
  return s;
}

inline std::unique_ptr<LibraryLaw> library_law(const std::filesystem::path& dir, std::int64_t template_id,
                                               const LibraryLawSettings& settings) {
  return std::make_unique<LibraryLaw>(std::make_unique<LibraryLink>(dir, template_id, nullptr), settings);
}

// The template as the library restores it (what a live law on the library starts from).
inline dem::DemCell stored_template(const std::filesystem::path& dir, std::int64_t template_id) {
  db::Library library = db::Library::open(dir);
  return library.restore(library.template_cell(template_id));
}

// 4 × 4 points in a 6 × 6 grid, velocity v = (γ̇ (y − y_c) + ε̇ (x − x_c), −ε̇ (y − y_c)): simple shear
// plus a little pure shear, so every point sees a different but smooth increment.
inline Solver block_with(std::unique_ptr<ConstitutiveLaw> law, double shear_rate = 2.0, double stretch_rate = 0.5) {
  SolverSettings settings;
  settings.transfer = {VelocityTransfer::Kind::flip_pic, std::numeric_limits<double>::infinity()};  // pure PIC
  Solver solver(Grid(Vec2(0, 0), 0.1, 6, 6), settings);
  solver.add_law(std::move(law));
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      const Vec2 x(0.225 + 0.05 * i, 0.225 + 0.05 * j);
      const Vec2 d = x - Vec2(0.3, 0.3);
      solver.add_point(0, x, 0.0025, 0.025, Vec2(shear_rate * d.y() + stretch_rate * d.x(), -stretch_rate * d.y()));
    }
  return solver;
}

inline double hit_rate(const Solver& solver) { return io::coupling_counters(solver, 0).hit_rate(); }

// Drives one point of a law outside the MPM step, as the step would: each increment F_inc over dt
// (at L = log F_inc / dt) and the point's deformation gradient composed from them.
class PointDriver {
 public:
  explicit PointDriver(std::size_t slot = 0) : slot_(slot) {}
  void operator()(ConstitutiveLaw& law, const Mat2& F_inc, double dt, PointStress& stress) {
    F_ = F_inc * F_;
    law.update(slot_, KinematicIncrement::of_deformation(F_inc, dt), F_, stress);
  }
  const Mat2& F() const { return F_; }

 private:
  std::size_t slot_;
  Mat2 F_ = Mat2::Identity();
};

}  // namespace grainbank::mpm::testing
