// The surrogate's answers have the mirror symmetry of a random packing (mirror_symmetry.hpp), on a
// real library whose samples do not: forty generated paths, each loading along its own axes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "database/store/library.hpp"
#include "database/surrogate/mirror_symmetry.hpp"
#include "database/surrogate/surrogate_step.hpp"
#include "tests/database/surrogate_test_util.hpp"

namespace grainbank::surrogate {
namespace {

class SurrogateMirror : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("grainbank-surrogate-mirror");
    db::Library library = test::build_library(*dir_, dir_->path() / "LIB", test::kGeneralPaths);
    dataset_ = new Dataset(reindex(library));
    index_ = test::fitted_index(*dataset_).release();
  }
  static void TearDownTestSuite() {
    delete index_;
    delete dataset_;
    delete dir_;
  }
  static test::TempDir* dir_;
  static Dataset* dataset_;
  static SurrogateIndex* index_;
};

test::TempDir* SurrogateMirror::dir_ = nullptr;
Dataset* SurrogateMirror::dataset_ = nullptr;
SurrogateIndex* SurrogateMirror::index_ = nullptr;

TEST_F(SurrogateMirror, AMirroredStateGetsTheMirroredAnswer) {
  double largest_shear = 0;
  for (const Sample& s : dataset_->samples) {
    const Prediction direct = index_->predict(s.features);
    const Prediction reflected = index_->predict(mirrored(s.features));
    const Answer image = mirrored(reflected.fit.answer);
    for (std::size_t c = 0; c < kAnswerSize; ++c) {
      const double scale = 1 + std::abs(direct.fit.answer[c]);
      ASSERT_NEAR(direct.fit.answer[c], image[c], 1e-12 * scale) << "component " << c;
      ASSERT_NEAR(direct.fit.error[c], reflected.fit.error[c], 1e-12 * (1 + direct.fit.error[c])) << "component " << c;
    }
    largest_shear = std::max(largest_shear, std::abs(direct.fit.answer[kMirrorOddAnswer]));
  }
  EXPECT_GT(largest_shear, 0.1);  // the odd component is not simply zero everywhere
}

// The samples' own Â_xy on the mirror plane: what a fit without the symmetry would start from.
TEST_F(SurrogateMirror, LoadingAlongAPrincipalAxisOfTheStressGivesNoShearRate) {
  double sample_shear = 0;
  int on_plane = 0;
  for (const Sample& s : dataset_->samples) {
    FeatureVector along_axes = s.features;
    along_axes[kMirrorOddFeature] = 0;  // β = 0 or ±π/2: D and σ share their principal axes
    const Prediction p = index_->predict(along_axes);
    EXPECT_EQ(p.fit.answer[kMirrorOddAnswer], 0.0);
    EXPECT_GE(p.fit.error[kMirrorOddAnswer], 0.0);
    sample_shear = std::max(sample_shear, std::abs(s.answer[kMirrorOddAnswer]));
    ++on_plane;
  }
  std::printf("%d queries on the mirror plane; the samples' largest |Â_xy| %.3f\n", on_plane, sample_shear);
  EXPECT_GT(sample_shear, 0.1);
}

// A point compressed along y from a state with σ's axes along x and y, as a column under gravity:
// by symmetry it never gains σ_xy, whatever the library holds.
TEST_F(SurrogateMirror, AnOedometricCompressionStaysFreeOfShearStress) {
  PointState state;
  const double p = dataset_->constants.p_ref;
  state.stress = dem::Mat3::Zero();
  state.stress(0, 0) = state.stress(2, 2) = -0.8 * p;
  state.stress(1, 1) = -1.4 * p;
  state.solid_fraction = dataset_->samples.front().features[3];
  state.coordination = dataset_->samples.front().features[4];
  dem::Mat3 L = dem::Mat3::Zero();
  L(1, 1) = -2.0;
  const double dt = 1e-4;
  for (int k = 0; k < 20; ++k) state = surrogate_step(*index_, state, L, dt, 0).state;
  EXPECT_EQ(state.stress(0, 1), 0.0);
  EXPECT_EQ(state.stress(1, 0), 0.0);
  EXPECT_LT(state.stress(1, 1), -1.4 * p);  // it was compressed
}

}  // namespace
}  // namespace grainbank::surrogate
