// State probes (dem_sampler/sampler/state_probes.hpp): each (base, depth, rate) is one path, a base
// segment and then ± pairs of probes whose dilatancy angle ψ, axis angle β and rate are the requested
// ones, measured here from the generated L with the definitions of the surrogate's key (3-D norms,
// plane strain); the probes of the in-plane isotropic bases do not repeat one another.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>

#include "dem_sampler/sampler/paths_input.hpp"
#include "dem_sampler/sampler/state_probes.hpp"
#include "tests/sampler/sampler_test_util.hpp"

namespace grainbank::sampler {
namespace {

constexpr double kDegree = std::numbers::pi / 180;

dem::Mat3 sym(const dem::Mat3& L) { return 0.5 * (L + L.transpose()); }

double psi_of(const dem::Mat3& L) {
  const dem::Mat3 D = sym(L);
  const dem::Mat3 dev = D - D.trace() / 3 * dem::Mat3::Identity();
  return std::atan2(D.trace(), dev.norm());
}

// The in-plane axis of D's largest eigenvalue, in [0, π).
double stretching_axis(const dem::Mat3& L) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(sym(L).topLeftCorner<2, 2>());
  const Eigen::Vector2d v = eig.eigenvectors().col(1);
  const double angle = std::atan2(v.y(), v.x());
  return angle < 0 ? angle + std::numbers::pi : (angle >= std::numbers::pi ? angle - std::numbers::pi : angle);
}

// Difference of two axis angles modulo π, in [0, π/2].
double axis_difference(double a, double b) {
  const double d = std::fmod(std::abs(a - b), std::numbers::pi);
  return std::min(d, std::numbers::pi - d);
}

ProbeSpec spec() {
  ProbeSpec s;
  s.bases = {ProbeBase::compression, ProbeBase::shear, ProbeBase::extension, ProbeBase::oedometric,
             ProbeBase::held_shear};
  s.depths = {0.01, 0.03};
  s.base_rate = 5;
  s.base_pressure = 400;
  s.psi = {-40 * kDegree, 0.0, 30 * kDegree, kMaxPlaneStrainPsi};
  s.beta = {0.0, 30 * kDegree, 90 * kDegree};
  s.rates = {1, 4};
  s.probe_strain = 0.002;
  s.record_interval = 2e-4;
  return s;
}

TEST(StateProbes, ExpandIntoBaseSegmentsAndPairsOfProbesOfTheRequestedDirections) {
  const ProbeSpec s = spec();
  const std::vector<PathPlan> plans = probe_paths(s);
  ASSERT_EQ(plans.size(), 5u * 2u * 2u);
  std::size_t k = 0;
  for (ProbeBase base : s.bases) {
    const bool held = base == ProbeBase::held_shear;
    const bool shear = base == ProbeBase::shear || held, oedometric = base == ProbeBase::oedometric;
    const bool axes = shear || oedometric;  // the base leaves in-plane stress axes, so every β is a probe
    const std::size_t directions = s.psi.size() * (axes ? s.beta.size() : 1);
    for (double depth : s.depths) {
      for (double rate : s.rates) {
        const auto& segments = plans[k++].path.segments;
        ASSERT_EQ(segments.size(), 1 + 2 * directions);
        const dem::Mat3 base_D = sym(segments[0].L);
        EXPECT_NEAR(base_D.norm(), s.base_rate, 1e-12);
        EXPECT_NEAR(base_D.norm() * segments[0].duration, depth, 1e-12);
        if (oedometric) {
          EXPECT_EQ(base_D(0, 0), 0) << "no lateral strain";
          EXPECT_NEAR(base_D(1, 1), -s.base_rate, 1e-12);
        } else {
          EXPECT_NEAR(base_D.trace(), shear ? 0.0 : (base == ProbeBase::compression ? -1 : 1) * std::sqrt(2.0) * s.base_rate,
                      1e-12);
        }
        if (shear) {
          EXPECT_EQ(segments[0].L(1, 0), 0) << "simple shear, with its spin";
        }
        // Only the held shear servoes its pressure; the probes are imposed as they are.
        EXPECT_EQ(segments[0].pressure, held ? s.base_pressure : 0.0);
        for (std::size_t j = 1; j < segments.size(); ++j) EXPECT_EQ(segments[j].pressure, 0.0);
        std::size_t d = 0;
        for (double psi : s.psi) {
          for (std::size_t b = 0; b < (axes ? s.beta.size() : 1); ++b, ++d) {
            const app::PathSegment& out = segments[1 + 2 * d];
            const app::PathSegment& back = segments[2 + 2 * d];
            EXPECT_EQ(back.L, -out.L);
            EXPECT_NEAR(sym(out.L).norm(), rate, 1e-12);
            EXPECT_NEAR(out.L(2, 2), 0, 0) << "plane strain";
            EXPECT_NEAR(sym(out.L).norm() * out.duration, s.probe_strain, 1e-15);
            EXPECT_NEAR(psi_of(out.L), psi, 1e-9);
            if (std::abs(psi) < kMaxPlaneStrainPsi - 1e-9) {  // at the limit D has no in-plane axes
              const double axis = shear ? std::numbers::pi / 4 + s.beta[b] : oedometric ? s.beta[b] : 0.0;
              EXPECT_LT(axis_difference(stretching_axis(out.L), axis), 1e-9);
            }
          }
        }
      }
    }
  }
}

TEST(StateProbes, AreReadFromPathsFilesWithTheirErrorsNamed) {
  const test::TempDir dir;
  const auto plans = load_paths_file(dir.write("paths.json", R"({
    "record_interval": 2e-4, "snapshot_interval": 5,
    "probes": [{"bases": ["shear"], "depths": [0.02], "base_rate": 5, "psi": [-30, 0, 30], "beta": [0, 90],
                "rates": [2], "probe_strain": 0.001}]})"));
  ASSERT_EQ(plans.size(), 1u);
  EXPECT_EQ(plans[0].path.segments.size(), 1u + 2 * 6);
  EXPECT_EQ(plans[0].snapshot_interval, 5);
  EXPECT_NEAR(psi_of(plans[0].path.segments[1].L), -30 * kDegree, 1e-9);

  const auto error_of = [&](const std::string& probe) {
    try {
      load_paths_file(dir.write("bad.json", R"({"record_interval": 2e-4, "probes": [)" + probe + "]}"));
    } catch (const common::InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string good = R"("depths": [0.02], "base_rate": 5, "beta": [0], "rates": [2], "probe_strain": 0.001)";
  const std::string steep = error_of(R"({"bases": ["shear"], "psi": [80], )" + good + "}");
  EXPECT_NE(steep.find("bad.json: /probes/0/psi/0"), std::string::npos) << steep;
  EXPECT_NE(steep.find("67.79"), std::string::npos) << steep;
  const std::string base = error_of(R"({"bases": ["twist"], "psi": [0], )" + good + "}");
  EXPECT_NE(base.find("/probes/0/bases/0: expected \"compression\", \"shear\", \"extension\", \"oedometric\" or "
                      "\"held_shear\""),
            std::string::npos)
      << base;
  const std::string unheld = error_of(R"({"bases": ["held_shear"], "psi": [0], )" + good + "}");
  EXPECT_NE(unheld.find("/probes/0/base_pressure: required"), std::string::npos) << unheld;
  const std::string stray = error_of(R"({"bases": ["shear"], "psi": [0], "base_pressure": 300, )" + good + "}");
  EXPECT_NE(stray.find("/probes/0/base_pressure: base_pressure is read by the held_shear base only"), std::string::npos)
      << stray;
  const auto held = load_paths_file(dir.write("held.json", R"({"record_interval": 2e-4, "probes": [{"bases": ["held_shear"],
    "base_pressure": 300, "psi": [0], )" + good + "}]}"));
  EXPECT_EQ(held[0].path.segments[0].pressure, 300);
  const std::string unknown = error_of(R"({"bases": ["shear"], "psi": [0], "angle": 3, )" + good + "}");
  EXPECT_NE(unknown.find("/probes/0/angle: unknown key"), std::string::npos) << unknown;
}

}  // namespace
}  // namespace grainbank::sampler
