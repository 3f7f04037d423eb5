// A point driven through loading then unloading gets the unloading stiffness from the state-keyed
// surrogate (issue 13). The total-strain key answers a stored stress at the same strain and rate,
// whatever the history; its numbers are printed for comparison, not asserted.
//
// Library: plane-strain compressions in four directions at two rates, each followed by a partial
// unloading (3 % then 1.5 %), and sixteen generated volumetric paths with a reversal. Held out: a
// uniaxial compression along y at another rate and to another strain (2.5 %), unloaded by 1.2 %,
// sampled in the same library but left out of both indexes. The DEM records of that path are the
// truth; the surrogate answers at the DEM's own states (one step each), and a point integrates its
// state along the path's L from the first record.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>

#include "database/lookup/lookup_index.hpp"
#include "database/store/library.hpp"
#include "database/surrogate/surrogate_step.hpp"
#include "tests/database/surrogate_test_util.hpp"

namespace grainbank::surrogate {
namespace {

constexpr const char* kPaths = R"({
  "record_interval": 5e-4,
  "paths": [
    {"segments": [{"L": [[-1.7677, 0], [0, -1.7677]], "strain": 0.03}, {"L": [[1.7677, 0], [0, 1.7677]], "strain": 0.015}]},
    {"segments": [{"L": [[0, 0], [0, -2.5]], "strain": 0.03}, {"L": [[0, 0], [0, 2.5]], "strain": 0.015}]},
    {"segments": [{"L": [[-2.5, 0], [0, 0]], "strain": 0.03}, {"L": [[2.5, 0], [0, 0]], "strain": 0.015}]},
    {"segments": [{"L": [[-2.0, 0.75], [0.75, -1.0]], "strain": 0.03}, {"L": [[2.0, -0.75], [-0.75, 1.0]], "strain": 0.015}]},
    {"segments": [{"L": [[-3.5355, 0], [0, -3.5355]], "strain": 0.03}, {"L": [[3.5355, 0], [0, 3.5355]], "strain": 0.015}]},
    {"segments": [{"L": [[0, 0], [0, -5.0]], "strain": 0.03}, {"L": [[0, 0], [0, 5.0]], "strain": 0.015}]},
    {"segments": [{"L": [[-5.0, 0], [0, 0]], "strain": 0.03}, {"L": [[5.0, 0], [0, 0]], "strain": 0.015}]},
    {"segments": [{"L": [[-4.0, 1.5], [1.5, -2.0]], "strain": 0.03}, {"L": [[4.0, -1.5], [-1.5, 2.0]], "strain": 0.015}]},
    {"segments": [{"L": [[0, 0], [0, -3.75]], "strain": 0.025}, {"L": [[0, 0], [0, 3.75]], "strain": 0.012}]}
  ],
  "generators": [{"count": 16, "rate": {"min": 2.5, "max": 7.5}, "strain": 0.04, "segments": 2,
                  "changes": ["reversal"], "volumetric": 1}]
})";

// dσ_yy/dε_yy over the intervals [a, b) (ε_yy = ln F_yy), from the stress change of each interval.
double modulus(const std::vector<db::Record>& records, std::size_t a, std::size_t b,
               const std::function<double(std::size_t)>& change) {
  double stress = 0;
  for (std::size_t k = a; k < b; ++k) stress += change(k);
  return stress / (std::log(records[b].F(1, 1)) - std::log(records[a].F(1, 1)));
}

TEST(SurrogateUnloading, APointUnloadsWithTheUnloadingStiffness) {
  const test::TempDir dir("grainbank-surrogate-unloading");
  db::Library library = test::build_library(dir, dir.path() / "LIB", kPaths);
  const std::int64_t held_out = 9;  // the last explicit path
  ASSERT_EQ(library.catalogue().path(held_out).spec.find("-3.75") != std::string::npos, true);

  Dataset dataset = reindex(library);
  std::erase_if(dataset.samples, [&](const Sample& s) { return s.origin.path_id == held_out; });
  const auto index = test::fitted_index(dataset);
  lookup::LookupIndex old_key(library.key_scales());
  for (const db::PathRow& path : library.catalogue().paths())
    if (path.id != held_out) old_key.insert(path.id, 0, library.records(path.id));

  const std::vector<db::Record> records = library.records(held_out);
  std::vector<dem::Mat3> truth, surrogate, total_strain;
  PointState state = point_state(records.front());
  double bound = 0;
  for (std::size_t k = 0; k < records.size(); ++k) {
    truth.push_back(db::from_stress6(records[k].stress));
    if (k > 0) {
      const SurrogateStep step = surrogate_step(*index, state, records[k].L, records[k].time - records[k - 1].time, 0);
      state = step.state;
      bound += step.estimated_error;
    }
    surrogate.push_back(state.stress);
    total_strain.push_back(old_key.query({records[k].F, records[k].L, records[k].damage}).stress);
  }
  // The reversal: the record where ln F_yy is smallest.
  std::size_t reversal = 0;
  for (std::size_t k = 0; k < records.size(); ++k)
    if (records[k].F(1, 1) < records[reversal].F(1, 1)) reversal = k;
  const std::size_t last = records.size() - 1;
  ASSERT_GT(reversal, 8u);
  ASSERT_GT(last - reversal, 5u);

  // Tangent moduli over the last four loading and the first four unloading intervals: the DEM's,
  // and the surrogate's answers from the DEM's own states (one step each).
  const auto dem_change = [&](std::size_t k) { return truth[k + 1](1, 1) - truth[k](1, 1); };
  const auto predicted_change = [&](std::size_t k) {
    const SurrogateStep step = surrogate_step(*index, point_state(records[k]), records[k + 1].L,
                                              records[k + 1].time - records[k].time, 0);
    return step.state.stress(1, 1) - truth[k](1, 1);
  };
  const double loading = modulus(records, reversal - 4, reversal, dem_change);
  const double unloading = modulus(records, reversal, reversal + 4, dem_change);
  const double predicted_loading = modulus(records, reversal - 4, reversal, predicted_change);
  const double predicted_unloading = modulus(records, reversal, reversal + 4, predicted_change);
  // The point integrated along the whole path, and the total-strain key, over the whole unloading.
  const auto chord = [&](const std::vector<dem::Mat3>& s) {
    return modulus(records, reversal, last, [&](std::size_t k) { return s[k + 1](1, 1) - s[k](1, 1); });
  };
  const double end_error = (surrogate[last] - truth[last]).norm(), old_end_error = (total_strain[last] - truth[last]).norm();
  std::printf("tangent moduli at the reversal: DEM loading %.3g Pa, unloading %.3g Pa; surrogate %.3g, %.3g Pa\n",
              loading, unloading, predicted_loading, predicted_unloading);
  std::printf("unloading chord: DEM %.3g Pa, integrated point %.3g Pa, total-strain key %.3g Pa\n", chord(truth),
              chord(surrogate), chord(total_strain));
  std::printf("stress error after unloading: integrated point %.0f Pa (estimate %.0f Pa), total-strain key %.0f Pa\n",
              end_error, bound, old_end_error);
  // The DEM cell unloads stiffer than it loads at the end of loading (the premise of the test).
  EXPECT_GT(unloading, 1.3 * loading);
  // At the same states the surrogate answers unloading with the unloading stiffness, and loading
  // with a softer one. (Measured: 2.9 and 3.7 MPa against the DEM's 2.3 and 3.6 MPa; the DEM's
  // loading tangent there holds one burst of bond breaking, which an average over neighbours
  // smooths out, so the loading tangent is only compared with the unloading one.) The library is a
  // chaotic DEM output that a build's floating-point path draws anew: over packing seeds 1-12 the
  // unloading tangent came −19 % to +22 % from the DEM's in the native build here (stop 61), and
  // −20.4 % in a portable build at this seed, so the band is 25 %.
  EXPECT_NEAR(predicted_unloading, unloading, 0.25 * unloading);
  EXPECT_GT(predicted_unloading, 1.15 * predicted_loading);
  // The point carrying its state unloads with the unloading stiffness (measured 4.2 against 3.5 MPa:
  // it reached the reversal 11 kPa above the DEM, having missed that burst), within the estimated
  // error.
  EXPECT_NEAR(chord(surrogate), chord(truth), 0.25 * chord(truth));
  EXPECT_LE(end_error, bound);
}

}  // namespace
}  // namespace grainbank::surrogate
