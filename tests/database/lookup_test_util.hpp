// Helpers of the lookup, merge and export tests: libraries holding paths of chosen records, built
// quickly (the template is an uncompressed random gas: lookup never simulates it).
#pragma once
#include <cmath>
#include <vector>

#include "dem_sampler/cell/matrix_functions.hpp"
#include "database/lookup/state_key.hpp"
#include "tests/database/store_test_util.hpp"

namespace grainbank::db::test {

inline std::int64_t add_gas_template(Library& library, ShardWriter& writer) {
  const dem::DemCell gas = dem::random_gas(library.material(), small_spec());
  return writer.add_template(library.material(), {{"kind", "test gas"}}, {gas.state(), gas.skin()});
}

// A done path of `records` in shard `shard` of the library; returns its id.
inline std::int64_t add_done_path(Library& library, const std::string& shard, const std::vector<Record>& records,
                                  const nlohmann::json& spec = {{"test", "path"}}) {
  ShardWriter writer(library, shard);
  const std::int64_t t = add_gas_template(library, writer);
  const std::int64_t path = library.add_path(t, spec, library.material());
  writer.start_path(path);
  writer.append_records(path, records);
  writer.finish_path(path, PathStatus::done, 1.5);
  return path;
}

inline dem::Mat3 rotation_z(double angle) {
  dem::Mat3 Q = dem::Mat3::Identity();
  Q(0, 0) = Q(1, 1) = std::cos(angle);
  Q(1, 0) = std::sin(angle);
  Q(0, 1) = -std::sin(angle);
  return Q;
}

// Record k of a constant-L plane-strain path F = exp(L t), with a stress that varies with the state.
inline Record path_record(const dem::Mat3& L, double t, double damage) {
  Record r;
  r.time = t;
  r.L = L;
  r.F = dem::matrix_exponential(L * t);
  r.damage = damage;
  r.stress = {-1e4 - 3e5 * t, -2e4 + 1e5 * t, -1.5e4, 4e3 * t + 50 * damage, 0, 0};
  r.bonds = 100;
  return r;
}

inline std::vector<Record> shear_path(int count, double rate = 1.0, double dt = 2e-3) {
  dem::Mat3 L = dem::Mat3::Zero();
  L(0, 1) = rate;
  std::vector<Record> records;
  for (int k = 0; k < count; ++k) records.push_back(path_record(L, dt * (k + 1), 0.01 * k));
  return records;
}

}  // namespace grainbank::db::test
