// Nearest-state lookup: exact answers at library states, interpolation, rotation back, k and
// tolerance, agreement with brute force, concurrent queries during insertion, refresh, counters.
#include <gtest/gtest.h>

#include <random>
#include <thread>

#include "database/lookup/lookup_index.hpp"
#include "tests/database/lookup_test_util.hpp"

namespace grainbank::lookup {
namespace {

using db::test::TempDir;

LookupState state_of(const db::Record& r) { return {r.F, r.L, r.damage}; }

double relative_difference(const dem::Mat3& a, const dem::Mat3& b) { return (a - b).norm() / b.norm(); }

// Random plane-strain states: stretch and rotation of a few percent, rates of order one.
std::vector<db::Record> random_records(std::size_t count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<db::Record> records(count);
  for (db::Record& r : records) {
    dem::Mat3 log_f = dem::Mat3::Zero();
    log_f(0, 0) = 0.05 * u(rng);
    log_f(1, 1) = 0.05 * u(rng);
    log_f(0, 1) = 0.05 * u(rng);
    log_f(1, 0) = 0.05 * u(rng);
    r.F = dem::matrix_exponential(log_f);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) r.L(i, j) = u(rng);
    r.damage = 0.5 * (1 + u(rng));
    for (int c = 0; c < 6; ++c) r.stress[c] = 1e4 * u(rng);
    r.stress[4] = r.stress[5] = 0;
  }
  return records;
}

TEST(LookupIndex, AnswersALibraryPathExactlyAtItsOwnStates) {
  TempDir tmp;
  db::Library library = db::Library::create(tmp.path() / "LIB", db::test::small_material());
  const std::vector<db::Record> records = db::test::shear_path(40);
  const std::int64_t path = db::test::add_done_path(library, "rank0", records);
  LookupIndex index(library.key_scales());
  ASSERT_EQ(index.refresh(library), records.size());
  for (std::size_t k = 0; k < records.size(); ++k) {
    const LookupAnswer a = index.query(state_of(records[k]));
    EXPECT_LE(a.distance, 1e-12) << k;
    EXPECT_TRUE(a.hit);
    EXPECT_EQ(a.nearest, (RecordRef{path, static_cast<std::int64_t>(k)}));
    EXPECT_EQ(a.estimated_error, 0.0);
    EXPECT_LT(relative_difference(a.stress, db::from_stress6(records[k].stress)), 1e-14) << k;
  }
}

TEST(LookupIndex, InterpolatesBetweenTwoRecordsByInverseSquareDistance) {
  LookupIndex index(db::KeyScales{1e-2, 1.0, 0.05});
  db::Record a = db::test::path_record(dem::Mat3::Zero(), 0, 0.0), b = a;
  a.coordination = 6;
  a.solid_fraction = 0.6;
  b.damage = 0.1;  // two key units from a; stress and the measures the MPM reads differ too
  b.stress = {-3e4, -1e4, -2e4, 1e3, 0, 0};
  b.coordination = 4;
  b.solid_fraction = 0.5;
  index.insert(-1, 0, {a, b});
  const dem::Mat3 sa = db::from_stress6(a.stress), sb = db::from_stress6(b.stress);

  const LookupAnswer middle = index.query({dem::Mat3::Identity(), dem::Mat3::Zero(), 0.05}, {2, 0.5});
  EXPECT_NEAR(middle.distance, 1.0, 1e-12);
  EXPECT_FALSE(middle.hit);
  EXPECT_LT(relative_difference(middle.stress, 0.5 * (sa + sb)), 1e-14);
  EXPECT_NEAR(middle.estimated_error, 0.5 * (sa - sb).norm(), 1e-9);
  EXPECT_NEAR(middle.damage, 0.05, 1e-15);
  EXPECT_NEAR(middle.coordination, 5, 1e-14);
  EXPECT_NEAR(middle.solid_fraction, 0.55, 1e-15);

  const LookupAnswer quarter = index.query({dem::Mat3::Identity(), dem::Mat3::Zero(), 0.025}, {2, 0.5});
  EXPECT_NEAR(quarter.distance, 0.5, 1e-12);
  EXPECT_TRUE(quarter.hit);
  const double wa = 1 / 0.25, wb = 1 / 2.25;
  EXPECT_LT(relative_difference(quarter.stress, (wa * sa + wb * sb) / (wa + wb)), 1e-14);
  EXPECT_NEAR(quarter.coordination, (wa * 6 + wb * 4) / (wa + wb), 1e-14);
  EXPECT_EQ(quarter.nearest, (RecordRef{-1, 0}));
}

TEST(LookupIndex, RotatedQueryReturnsRotatedStress) {
  const std::vector<db::Record> records = db::test::shear_path(30);
  LookupIndex index(db::KeyScales{});
  index.insert(7, 0, records);
  for (double angle : {0.4, -1.3, 2.8}) {
    const dem::Mat3 Q = db::test::rotation_z(angle);
    for (std::size_t k : {0, 11, 29}) {
      const db::Record& r = records[k];
      const LookupAnswer a = index.query({Q * r.F, Q * r.L * Q.transpose(), r.damage});
      EXPECT_LE(a.distance, 1e-9);
      EXPECT_LT(relative_difference(a.stress, Q * db::from_stress6(r.stress) * Q.transpose()), 1e-12);
    }
  }
  // A record stored in a rotated lab frame answers the unrotated query with the unrotated stress.
  LookupIndex rotated(db::KeyScales{});
  const dem::Mat3 Q = db::test::rotation_z(0.9);
  db::Record r = records[20];
  const dem::Mat3 sigma = db::from_stress6(r.stress);
  r.F = Q * r.F;
  r.L = Q * r.L * Q.transpose();
  r.stress = db::to_stress6(Q * sigma * Q.transpose());
  rotated.insert(1, 0, {r});
  EXPECT_LT(relative_difference(rotated.query(state_of(records[20])).stress, sigma), 1e-12);
}

TEST(LookupIndex, KAndToleranceBehaviour) {
  LookupIndex index(db::KeyScales{});
  const LookupAnswer empty = index.query({});
  EXPECT_EQ(empty.neighbours, 0u);
  EXPECT_FALSE(empty.hit);
  EXPECT_TRUE(std::isinf(empty.distance));

  const std::vector<db::Record> records = random_records(200, 3);
  index.insert(-1, 0, records);
  LookupState probe = state_of(records[5]);
  probe.damage += 0.3 * db::KeyScales{}.damage;  // 0.3 key units away from record 5
  const LookupAnswer one = index.query(probe, {1, 0.5});
  EXPECT_EQ(one.neighbours, 1u);
  EXPECT_EQ(one.nearest, (RecordRef{-1, 5}));
  EXPECT_NEAR(one.distance, 0.3, 1e-9);
  EXPECT_EQ(one.estimated_error, 0.0);
  EXPECT_LT(relative_difference(one.stress, db::from_stress6(records[5].stress)), 1e-12);
  EXPECT_TRUE(one.hit);
  EXPECT_FALSE(index.query(probe, {1, 0.29}).hit);
  EXPECT_TRUE(index.query(probe, {1, 0.31}).hit);
  EXPECT_EQ(index.query(probe, {500, 0.5}).neighbours, 200u);
  EXPECT_GT(index.query(probe, {8, 0.5}).estimated_error, 0.0);
  EXPECT_THROW(index.query(probe, {0, 0.5}), std::invalid_argument);
}

// A state far outside the library (hard case of issue 8): a miss at a large, finite distance whose
// answer is a convex blend of stored stresses (1/d² weights), never an extrapolation or NaN.
TEST(LookupIndex, AStateFarOutsideTheLibraryMissesWithAFiniteStoredAnswer) {
  LookupIndex index(db::KeyScales{});
  const std::vector<db::Record> records = random_records(200, 7);
  index.insert(-1, 0, records);
  LookupState far;
  far.F = dem::Mat3::Identity();
  far.F(0, 0) = 3.0;   // 300 % stretch, 70 % compression: the library holds a few percent
  far.F(1, 1) = 0.3;
  far.L(0, 1) = 1e4;   // and a rate 10⁴ times the library's
  far.damage = 1.0;
  const LookupAnswer a = index.query(far, {8, 0.5});
  EXPECT_FALSE(a.hit);
  EXPECT_TRUE(std::isfinite(a.distance));
  EXPECT_GT(a.distance, 1e3);
  EXPECT_TRUE(a.stress.allFinite());
  EXPECT_TRUE(std::isfinite(a.estimated_error));
  double largest = 0;
  for (const db::Record& r : records) largest = std::max(largest, db::from_stress6(r.stress).norm());
  EXPECT_LE(a.stress.norm(), largest * (1 + 1e-12));  // within the stored range (rotation keeps the norm)
  EXPECT_GE(a.damage, 0.0);
  EXPECT_LE(a.damage, 1.0);
}

TEST(LookupIndex, MatchesBruteForceOnRandomData) {
  LookupIndex index(db::KeyScales{0.02, 0.5, 0.1});
  const std::vector<db::Record> records = random_records(6000, 11);
  // Uneven batches, so the index holds several kd-tree blocks (and merges some).
  std::size_t first = 0;
  for (std::size_t batch : {2500, 700, 1, 1500, 300, 999}) {
    index.insert(-1, static_cast<std::int64_t>(first),
                 std::vector<db::Record>(records.begin() + first, records.begin() + first + batch));
    first += batch;
  }
  ASSERT_EQ(index.size(), records.size());
  for (const db::Record& q : random_records(300, 12)) {
    const LookupAnswer fast = index.query(state_of(q), {4, 1.0});
    const LookupAnswer slow = index.query_brute_force(state_of(q), {4, 1.0});
    EXPECT_EQ(fast.nearest, slow.nearest);
    EXPECT_EQ(fast.distance, slow.distance);
    EXPECT_LT(relative_difference(fast.stress, slow.stress), 1e-12);
    EXPECT_NEAR(fast.estimated_error, slow.estimated_error, 1e-9 * slow.stress.norm());
  }
}

// Path-like keys (dense along curves, as a sampled library), inserted in many blocks of uneven
// size: the search of each block starts from the k-th best distance of the larger blocks before it
// and must still return exactly the scan's neighbours, near the paths (hits) and far from them.
TEST(LookupIndex, MatchesBruteForceOnPathDataAcrossManyBlocks) {
  LookupIndex index(db::KeyScales{1e-2, 1.0, 0.05});
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<db::Record> all;
  std::int64_t path = 0;
  for (std::size_t length : {900, 50, 400, 3, 1200, 77, 600, 1, 250, 30}) {
    dem::Mat3 L = dem::Mat3::Zero();
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) L(i, j) = u(rng);
    std::vector<db::Record> records;
    for (std::size_t k = 0; k < length; ++k) records.push_back(db::test::path_record(L, 5e-5 * static_cast<double>(k + 1), 1e-4 * static_cast<double>(k)));
    index.insert(++path, 0, records);
    all.insert(all.end(), records.begin(), records.end());
  }
  ASSERT_EQ(index.size(), all.size());
  std::normal_distribution<double> n;
  for (int q = 0; q < 400; ++q) {
    LookupState probe = state_of(all[static_cast<std::size_t>(q * 7919) % all.size()]);
    const double off = q % 4 == 0 ? 3.0 : 0.1;  // a quarter far from every path
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) probe.L(i, j) += off * n(rng);
    probe.damage += off * 0.05 * n(rng);
    for (std::size_t k : {1, 4, 9}) {
      const LookupAnswer fast = index.query(probe, {k, 0.5});
      const LookupAnswer slow = index.query_brute_force(probe, {k, 0.5});
      EXPECT_EQ(fast.nearest, slow.nearest) << q << " k " << k;
      EXPECT_EQ(fast.distance, slow.distance);
      EXPECT_EQ(fast.hit, slow.hit);
      EXPECT_EQ(fast.neighbours, slow.neighbours);
      EXPECT_LT(relative_difference(fast.stress, slow.stress), 1e-12);
    }
  }
}

TEST(LookupIndex, ConcurrentQueriesDuringInsertionMatchSerialAnswers) {
  LookupIndex index(db::KeyScales{0.02, 0.5, 0.1});
  index.insert(-1, 0, random_records(20000, 21));
  const std::vector<db::Record> queries = random_records(2000, 22);
  std::vector<LookupAnswer> serial;
  for (const db::Record& q : queries) serial.push_back(index.query(state_of(q)));

  // Far away in damage (key ~ 1000 units): inserting them must not change any answer.
  std::vector<db::Record> far = random_records(4000, 23);
  for (db::Record& r : far) r.damage += 100;
  std::vector<std::vector<LookupAnswer>> parallel(4);
  std::vector<std::thread> threads;
  for (auto& answers : parallel)
    threads.emplace_back([&] {
      for (const db::Record& q : queries) answers.push_back(index.query(state_of(q)));
    });
  for (std::size_t k = 0; k < far.size(); k += 250)
    index.insert(-2, static_cast<std::int64_t>(k), std::vector<db::Record>(far.begin() + k, far.begin() + k + 250));
  for (std::thread& t : threads) t.join();

  EXPECT_EQ(index.size(), 24000u);
  for (const auto& answers : parallel)
    for (std::size_t k = 0; k < queries.size(); ++k) {
      EXPECT_EQ(answers[k].nearest, serial[k].nearest);
      EXPECT_EQ(answers[k].distance, serial[k].distance);
      EXPECT_EQ(answers[k].stress, serial[k].stress);
    }
}

TEST(LookupIndex, RefreshIndexesDonePathsOnceAndPicksUpNewOnes) {
  TempDir tmp;
  db::Library library = db::Library::create(tmp.path() / "LIB", db::test::small_material());
  db::test::add_done_path(library, "rank0", db::test::shear_path(10));
  db::ShardWriter writer(library, "rank1");
  const std::int64_t t = db::test::add_gas_template(library, writer);
  const std::int64_t running = library.add_path(t, {{"p", 2}}, library.material());
  writer.start_path(running);
  writer.append_records(running, db::test::shear_path(5, -2.0));

  LookupIndex index(library.key_scales());
  EXPECT_EQ(index.refresh(library), 10u);
  EXPECT_EQ(index.refresh(library), 0u);
  writer.finish_path(running, db::PathStatus::done, 1.0);
  EXPECT_EQ(index.refresh(library), 5u);
  EXPECT_EQ(index.size(), 15u);
}

}  // namespace
}  // namespace grainbank::lookup
