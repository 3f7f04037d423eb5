// The pressure floor of the surrogate's normalization (reindex.hpp): below its preparation pressure
// a bonded packing is overconsolidated and unloads at the stiffness its contacts and bonds were made
// with. Measured on a real DEM unloading of the test template (64 bonded spheres prepared at
// 1000 Pa, in-plane isotropic stretch through zero into tension): its answers normalized with the
// floor at p_ref are one answer wherever the cell is below p_ref, while the default floor (p_ref/10)
// spreads the same elastic unloading over the 1/p of its normalization.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "database/store/library.hpp"
#include "tests/database/surrogate_test_util.hpp"

namespace grainbank::surrogate {
namespace {

// |D| = 0.5 /s, quasi-static (I ≈ 2e-4): 40 records of 2e-5 s take the cell from 1000 Pa into tension.
constexpr const char* kUnloading = R"({
  "record_interval": 2e-5,
  "paths": [{"segments": [{"L": [[0.3536, 0], [0, 0.3536]], "duration": 8e-4}]}]
})";

struct Unloading {
  std::vector<double> pressure;       // −tr σ / 3 before each interval [Pa]
  std::vector<double> volume_answer;  // (Â_xx + Â_yy + Â_zz) / 3 of its sample
};

// The samples of states between `low` and `high` times p_ref, in path order.
Unloading unloading(const Dataset& dataset, db::Library& library, double low, double high) {
  const std::int64_t path = library.catalogue().paths().front().id;
  const std::vector<db::Record> records = library.records(path);
  Unloading u;
  for (const Sample& s : dataset.samples) {
    const double p = -db::from_stress6(records.at(static_cast<std::size_t>(s.origin.record_index)).stress).trace() / 3;
    if (p < low * dataset.constants.p_ref || p > high * dataset.constants.p_ref) continue;
    u.pressure.push_back(p);
    u.volume_answer.push_back((s.answer[0] + s.answer[1] + s.answer[2]) / 3);
  }
  return u;
}

double spread(const std::vector<double>& v) {
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  return *hi / *lo;
}

TEST(SurrogatePressureFloor, AtThePreparationPressureAnElasticUnloadingIsOneAnswer) {
  const test::TempDir dir("grainbank-surrogate-floor");
  db::Library library = test::build_library(dir, dir.path() / "LIB", kUnloading);
  const Dataset at_preparation = reindex(library, 1, 1.0);
  const Dataset at_default = reindex(library, 1);
  EXPECT_DOUBLE_EQ(at_preparation.constants.p_floor, at_preparation.constants.p_ref);
  EXPECT_DOUBLE_EQ(at_default.constants.p_floor, at_default.constants.p_ref / 10);
  EXPECT_EQ(at_default.constants.p_ref, at_preparation.constants.p_ref);

  // The cell unloads from 0.8 p_ref to 0.2 p_ref: a factor 4 in p.
  const Unloading elastic = unloading(at_preparation, library, 0.2, 0.8);
  const Unloading relative = unloading(at_default, library, 0.2, 0.8);
  ASSERT_GE(elastic.pressure.size(), 5u);
  ASSERT_EQ(relative.pressure.size(), elastic.pressure.size());
  ASSERT_GT(*std::max_element(elastic.pressure.begin(), elastic.pressure.end()),
            2 * *std::min_element(elastic.pressure.begin(), elastic.pressure.end()));
  // Unloading: the pressure falls (tension-positive answers, > 0).
  for (double a : elastic.volume_answer) EXPECT_GT(a, 0);
  std::printf("unloading from %.0f to %.0f Pa: answer spread %.2f at the floor p_ref, %.2f at p_ref / 10\n",
              elastic.pressure.front(), elastic.pressure.back(), spread(elastic.volume_answer),
              spread(relative.volume_answer));
  // One stiffness: the cell's own, within a quarter, once p no longer scales the answer.
  EXPECT_LT(spread(elastic.volume_answer), 1.25);
  // Normalized by p, the same unloading's answer grows as the pressure falls.
  EXPECT_GT(spread(relative.volume_answer), 2.5);
}

TEST(SurrogatePressureFloor, AFloorMustBeAShareOfThePreparationPressure) {
  const test::TempDir dir("grainbank-surrogate-floor-bad");
  db::Library library = test::build_library(dir, dir.path() / "LIB", kUnloading);
  for (double bad : {0.0, -0.1, 1.5})
    EXPECT_THROW(library_constants(library, bad), std::invalid_argument) << bad;
  EXPECT_NO_THROW(library_constants(library, 1.0));
}

}  // namespace
}  // namespace grainbank::surrogate
