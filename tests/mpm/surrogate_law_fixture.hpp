// The fixture of the surrogate law's tests (issue 13): a small real library sampled in-process
// (forty generated two-segment paths of the 64-sphere cohesive cell,
// tests/database/surrogate_test_util.hpp), built once per test process, and a driver that steps one
// point of a law as the MPM step would.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "tests/database/surrogate_test_util.hpp"
#include "mpm_solver/dem_laws/library_link.hpp"
#include "mpm_solver/dem_laws/surrogate_law.hpp"
#include "database/store/library.hpp"

namespace grainbank::mpm::surrogate_law_fixture {

inline constexpr double kDt = 2e-4;  // the library's record interval
inline constexpr double kNoLimit = std::numeric_limits<double>::infinity();

// The library, its template and its dataset, built once for the whole process.
struct SharedLibrary {
  surrogate::test::TempDir dir{"grainbank-surrogate-law"};
  std::filesystem::path path = dir.path() / "LIB";
  std::int64_t template_id = 0;
  std::optional<dem::DemCell> cell;
  surrogate::Dataset dataset;
  std::vector<std::vector<db::Record>> paths;
  std::vector<StateSnapshot> snapshots;
};

inline const SharedLibrary& shared() {
  static const SharedLibrary* const library = [] {
    auto* s = new SharedLibrary;
    db::Library library = surrogate::test::build_library(s->dir, s->path, surrogate::test::kGeneralPaths);
    s->template_id = library.catalogue().templates().front().id;
    s->cell.emplace(library.restore(library.template_cell(s->template_id)));
    s->dataset = surrogate::reindex(library);
    for (const db::PathRow& path : library.catalogue().paths()) s->paths.push_back(library.records(path.id));
    s->snapshots = LibraryLink(s->path, s->template_id, nullptr).state_snapshots();
    return s;
  }();
  return *library;
}

inline SurrogateLawSettings settings(double tolerance, int return_after = 0) {
  SurrogateLawSettings s;
  s.tolerance = tolerance;
  s.return_after = return_after;
  return s;
}

inline std::unique_ptr<SurrogateLaw> surrogate_law(const SurrogateLawSettings& s) {
  return std::make_unique<SurrogateLaw>(*shared().cell, shared().dataset, s, shared().snapshots);
}

// Drives one point of a law through increments at constant L, as the MPM step would.
struct Driver {
  std::size_t slot = 0;
  Mat2 F = Mat2::Identity();
  PointStress stress;
  // The point's update within a step; the step ends when every point of it was updated.
  void update(ConstitutiveLaw& law, const Mat2& L, double dt) {
    const KinematicIncrement increment = KinematicIncrement::of_velocity_gradient(L, dt);
    F = increment.F * F;
    law.update(slot, increment, F, stress);
  }
  // A step of this point alone.
  void operator()(ConstitutiveLaw& law, const Mat2& L, double dt) {
    update(law, L, dt);
    law.end_step();
  }
};

inline Driver new_point(ConstitutiveLaw& law) {
  Driver d;
  d.slot = law.add_point(d.stress);
  return d;
}

// A motion the library's 0.4 % paths do not cover: 2 % of compression (both in-plane axes) with shear.
inline std::vector<Mat2> off_library_motion() {
  return std::vector<Mat2>(60, Mat2{{-1.5, 1.0}, {0.0, -0.5}});
}

inline double stress_distance(const PointStress& a, const PointStress& b) {
  return std::sqrt((a.in_plane - b.in_plane).squaredNorm() + (a.zz - b.zz) * (a.zz - b.zz));
}

// The per-step estimated errors of a point along `motion` answered by the surrogate alone.
inline std::vector<double> surrogate_errors(const std::vector<Mat2>& motion) {
  auto law = surrogate_law(settings(kNoLimit));
  Driver d = new_point(*law);
  std::vector<double> errors;
  for (const Mat2& L : motion) {
    d(*law, L, kDt);
    errors.push_back(law->estimated_error(d.slot));
  }
  return errors;
}

// A tolerance the motion exceeds about halfway.
inline double median_tolerance(const std::vector<Mat2>& motion) {
  std::vector<double> errors = surrogate_errors(motion);
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  return errors[errors.size() / 2];
}


}  // namespace grainbank::mpm::surrogate_law_fixture
