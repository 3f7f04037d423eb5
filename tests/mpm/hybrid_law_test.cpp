// The hybrid law: with an empty library it is the live law (to round-off); a point that misses turns
// live with a cell whose deformation is the point's F (warm start from a snapshot, or replay of its
// own increments, which reproduces a live point exactly).
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "tests/mpm/coupling_test_util.hpp"
#include "mpm_solver/io/restart.hpp"
#include "mpm_solver/io/tracked_cells.hpp"

namespace grainbank::mpm {
namespace {

using namespace testing;

constexpr double kDt = 2e-4;

void expect_same_stress(const PointStress& a, const PointStress& b, double relative) {
  const double scale = std::abs(b.in_plane.trace()) + std::abs(b.zz);
  EXPECT_LE((a.in_plane - b.in_plane).norm(), relative * scale);
  EXPECT_LE(std::abs(a.zz - b.zz), relative * scale);
}

TEST(HybridLaw, EmptyLibraryEqualsLiveToRoundOff) {
  const auto dir = fresh_library_dir();
  const std::int64_t id = create_library(dir, small_snow_cell());
  LiveDemSettings live;
  live.substepping = {0.1, 1, 0.2};
  Solver reference = block_with(std::make_unique<LiveDemLaw>(stored_template(dir, id), live));
  Solver hybrid = block_with(library_law(dir, id, coupling_settings(Fallback::warm_start, false)));
  for (int step = 0; step < 6; ++step) {
    EXPECT_EQ(reference.stable_time_step(), hybrid.stable_time_step());
    reference.step(kDt);
    hybrid.step(kDt);
    for (std::size_t k = 0; k < reference.points().size(); ++k) {
      const MaterialPoint &a = hybrid.points()[k], &b = reference.points()[k];
      ASSERT_EQ(a.id, b.id);
      expect_same_stress(a.stress, b.stress, 1e-12);
      EXPECT_NEAR(a.volume, b.volume, 1e-12 * b.volume);
      EXPECT_EQ(a.position, b.position);
      EXPECT_EQ(stress_source(hybrid.law(0), a.slot), StressSource::live);
    }
  }
  const CouplingCounters c = io::coupling_counters(hybrid, 0);
  EXPECT_EQ(c.went_live, 16u);
  EXPECT_EQ(c.misses, 16u);
  EXPECT_EQ(c.hits, 0u);
  EXPECT_EQ(c.warm_start_increments, 0u);  // started from the template itself: nothing to drive
  EXPECT_EQ(c.live_updates, 16u * 6);
  // Tracked points of a hybrid run write the cell a live point would own.
  const std::uint32_t tracked = reference.points()[3].id;
  const dem::DemCell *live_cell = io::cell_of_point(reference, tracked),
                    *hybrid_cell = io::cell_of_point(hybrid, tracked);
  ASSERT_NE(hybrid_cell, nullptr);
  EXPECT_EQ(hybrid_cell->cell_matrix(), live_cell->cell_matrix());
  EXPECT_EQ(hybrid_cell->positions(), live_cell->positions());
}

TEST(HybridLaw, RestartContinuesExactlyLikeTheUninterruptedRun) {
  const auto dir = fresh_library_dir();
  const std::int64_t id = create_library(dir, small_snow_cell());
  const auto settings = coupling_settings(Fallback::warm_start, false);
  Solver uninterrupted = block_with(library_law(dir, id, settings));
  for (int step = 0; step < 3; ++step) uninterrupted.step(kDt);
  const auto file = dir / "restart.h5";
  io::write_restart(file, uninterrupted);
  for (int step = 0; step < 3; ++step) uninterrupted.step(kDt);

  Solver resumed = block_with(library_law(dir, id, settings));
  io::read_restart(file, resumed);
  for (int step = 0; step < 3; ++step) resumed.step(kDt);
  for (std::size_t k = 0; k < resumed.points().size(); ++k) {
    EXPECT_EQ(resumed.points()[k].stress.in_plane, uninterrupted.points()[k].stress.in_plane);
    EXPECT_EQ(resumed.points()[k].position, uninterrupted.points()[k].position);
    EXPECT_EQ(stress_source(resumed.law(0), resumed.points()[k].slot), StressSource::live);
  }
}

// A library holding the exact path of one point sheared for 24 increments (written by a hybrid
// point on the empty library, with a snapshot every 4 records). A point follows that path for 14
// increments (hits), then is compressed instead: it misses and turns live.
class MissingPoint : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fresh_library_dir();
    id_ = create_library(dir_, small_snow_cell());
    auto writer = library_law(dir_, id_, coupling_settings(Fallback::warm_start, true));
    PointStress s;
    writer->add_point(s);
    PointDriver drive;
    for (int k = 0; k < 24; ++k) drive(*writer, shear_, kDt, s);
    writer->finish();
    for (int k = 0; k < 14; ++k) increments_.push_back(shear_);
    for (int k = 0; k < 4; ++k) increments_.push_back(compression_);
  }
  // Drives a new point of `law` through increments_; returns the point's F.
  Mat2 drive(LibraryLaw& law) const {
    PointStress s;
    PointDriver drive(law.add_point(s));
    for (const Mat2& inc : increments_) drive(law, inc, kDt, s);
    return drive.F();
  }
  const Mat2 shear_ = Mat2::Identity() + kDt * Mat2{{-0.3, 1.0}, {0.0, -0.2}};
  const Mat2 compression_ = Mat2::Identity() + kDt * Mat2{{-3.0, 0.0}, {0.0, 1.0}};
  std::filesystem::path dir_;
  std::int64_t id_ = 0;
  std::vector<Mat2> increments_;
};

TEST_F(MissingPoint, GoesLiveFromASnapshotWithTheCellDeformationOfThePoint) {
  LibraryLawSettings s = coupling_settings(Fallback::warm_start, false);
  s.max_drive_strain = 5e-5;
  auto law = library_law(dir_, id_, s);
  const Mat2 F = drive(*law);
  const CouplingCounters c = law->counters();
  EXPECT_EQ(c.hits, 14u);
  EXPECT_EQ(c.misses, 1u);
  EXPECT_EQ(c.went_live, 1u);
  EXPECT_EQ(c.live_updates, 4u);
  // The only point holds every count (the VTU fields hits, misses, live_steps).
  EXPECT_EQ(law->point_counters(0).hits, c.hits);
  EXPECT_EQ(law->point_counters(0).misses, c.misses);
  EXPECT_EQ(law->point_counters(0).live_updates, c.live_updates);
  // From the snapshot after record 11 (12 increments) to the point's F after 14: driven over 2
  // increments' worth of strain in steps of at most max_drive_strain.
  EXPECT_GE(c.warm_start_increments, 2u);
  const dem::DemCell* cell = law->live_cell(0);
  ASSERT_NE(cell, nullptr);
  EXPECT_EQ(law->source(0), StressSource::live);
  const dem::Mat3 cell_F = cell->deformation_gradient();
  EXPECT_LE((cell_F.topLeftCorner<2, 2>() - F).norm(), 1e-12);
  EXPECT_LE((cell_F.row(2) - dem::Vec3(0, 0, 1).transpose()).norm(), 1e-12);
  EXPECT_LE((cell_F.col(2) - dem::Vec3(0, 0, 1)).norm(), 1e-12);
}

TEST_F(MissingPoint, ReplayRebuildsTheCellALivePointWouldOwn) {
  auto law = library_law(dir_, id_, coupling_settings(Fallback::replay, false));
  LiveDemSettings live;
  live.substepping = coupling_settings(Fallback::replay, false).live.substepping;
  LiveDemLaw reference(stored_template(dir_, id_), live);
  drive(*law);
  PointStress expected;
  reference.add_point(expected);
  PointDriver drive;
  for (const Mat2& inc : increments_) drive(reference, inc, kDt, expected);
  EXPECT_EQ(law->counters().warm_start_increments, 14u);  // the increments before the miss, replayed
  const dem::DemCell* cell = law->live_cell(0);
  ASSERT_NE(cell, nullptr);
  EXPECT_EQ(cell->time(), reference.cell(0).time());
  EXPECT_EQ(cell->cell_matrix(), reference.cell(0).cell_matrix());
  EXPECT_EQ(cell->measures().stress, reference.cell(0).measures().stress);
}

// A lone front point can be sheared until det F is round-off of either sign (stop 73: |F| ~ 1e8). The
// total-strain key has no polar decomposition of such an F: a live point stays live, a point rebuilt
// by replay goes live, and a point that a warm start or the cache would answer from F stops the run
// with the remedy.
TEST_F(MissingPoint, APointWhoseFIsInvertedByRoundOffIsAnsweredByALiveCellOrStopsWithTheRemedy) {
  const Mat2 inverted{{1.4e8, 1.4e8}, {-1e-8, -1.2e-8}};  // det F = -0.28
  ASSERT_LT(inverted.determinant(), 0);
  const KinematicIncrement step = KinematicIncrement::of_deformation(shear_, kDt);
  PointStress s;

  LibraryLawSettings returning = coupling_settings(Fallback::warm_start, false);
  returning.return_after = 1;
  auto live = library_law(dir_, id_, returning);
  drive(*live);
  ASSERT_NE(live->live_cell(0), nullptr) << "the set-up must turn the point live";
  live->update(0, step, inverted, s);
  EXPECT_NE(live->live_cell(0), nullptr);
  EXPECT_EQ(live->source(0), StressSource::live);
  EXPECT_TRUE(s.in_plane.allFinite());

  auto replayed = library_law(dir_, id_, coupling_settings(Fallback::replay, false));
  replayed->add_point(s);
  replayed->update(0, step, inverted, s);
  EXPECT_EQ(replayed->source(0), StressSource::live);
  EXPECT_EQ(replayed->counters().misses, 1u);

  for (const Fallback fallback : {Fallback::warm_start, Fallback::none}) {
    auto law = library_law(dir_, id_, coupling_settings(fallback, false));
    law->add_point(s);
    try {
      law->update(0, step, inverted, s);
      FAIL() << law->name() << " answered a point whose F has no polar decomposition";
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      for (const char* part : {"det F = -0.28", "no total strain the library's key can place", "\"replay\"",
                               "the surrogate law"})
        EXPECT_NE(what.find(part), std::string::npos) << part << " not in: " << what;
    }
  }
}

// Restart files of a LibraryLaw point driven directly (outside the MPM step, so its increments are
// the fixture's): `steps` increments, then a restart, then the rest in a law rebuilt from the file.
class RestartedPoint : public MissingPoint {
 protected:
  Solver solver_with_one_point(const LibraryLawSettings& settings) const {
    Solver solver(Grid(Vec2(0, 0), 0.1, 6, 6), SolverSettings{});
    solver.add_law(library_law(dir_, id_, settings));
    solver.add_point(0, Vec2(0.3, 0.3), 0.0025, 0.025, Vec2::Zero());
    return solver;
  }
  static LibraryLaw& law_of(Solver& solver) { return dynamic_cast<LibraryLaw&>(solver.law(0)); }
  // The solver whose law went through `increments` with a restart after the first `before_restart`.
  Solver resumed_after(const LibraryLawSettings& settings, const std::vector<Mat2>& increments,
                       std::size_t before_restart) const {
    Solver first = solver_with_one_point(settings);
    PointStress s;
    PointDriver drive;
    for (std::size_t k = 0; k < before_restart; ++k) drive(law_of(first), increments[k], kDt, s);
    const auto file = dir_ / "restart.h5";
    io::write_restart(file, first);
    Solver resumed = solver_with_one_point(settings);
    io::read_restart(file, resumed);
    for (std::size_t k = before_restart; k < increments.size(); ++k) drive(law_of(resumed), increments[k], kDt, s);
    return resumed;
  }
};

TEST_F(RestartedPoint, KeepsTheReplayHistory) {
  const LibraryLawSettings settings = coupling_settings(Fallback::replay, false);
  auto uninterrupted = library_law(dir_, id_, settings);
  drive(*uninterrupted);
  Solver resumed = resumed_after(settings, increments_, 14);  // restarted among the hits
  const LibraryLaw& law = law_of(resumed);
  EXPECT_EQ(law.counters().warm_start_increments, 14u);  // all 14 replayed, not only those since the restart
  const dem::DemCell *cell = law.live_cell(0), *expected = uninterrupted->live_cell(0);
  ASSERT_NE(cell, nullptr);
  ASSERT_NE(expected, nullptr);
  EXPECT_EQ(cell->time(), expected->time());
  EXPECT_EQ(cell->cell_matrix(), expected->cell_matrix());
  EXPECT_EQ(cell->measures().stress, expected->measures().stress);
}

TEST_F(RestartedPoint, KeepsTheCountOfLiveStepsBackInsideTheTolerance) {
  LibraryLawSettings settings = coupling_settings(Fallback::warm_start, false);
  settings.return_after = 3;
  // 14 hits, off the path (live), back onto it (F as after 14), then 3 increments along it.
  std::vector<Mat2> increments(increments_.begin(), increments_.begin() + 15);
  increments.push_back(compression_.inverse());
  for (int k = 0; k < 3; ++k) increments.push_back(shear_);
  auto uninterrupted = library_law(dir_, id_, settings);
  PointStress s;
  const std::size_t slot = uninterrupted->add_point(s);
  PointDriver drive(slot);
  std::vector<bool> live;
  for (const Mat2& inc : increments) {
    drive(*uninterrupted, inc, kDt, s);
    live.push_back(uninterrupted->live_cell(slot) != nullptr);
  }
  ASSERT_FALSE(live[13]);
  ASSERT_TRUE(live[14] && live[17]) << "the set-up must turn the point live and keep it live";
  ASSERT_FALSE(live.back()) << "the set-up must bring the point back to the cache";
  // Restarted after 2 of the 3 steps back inside: the third returns it to the cache, as without restart.
  Solver resumed = resumed_after(settings, increments, increments.size() - 1);
  EXPECT_EQ(law_of(resumed).live_cell(0), nullptr);
  EXPECT_EQ(law_of(resumed).counters().returned_to_cache, 1u);
}

}  // namespace
}  // namespace grainbank::mpm
