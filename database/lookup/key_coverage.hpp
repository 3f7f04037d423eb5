// How much of the key space a library covers (`celldb info`): over the committed records of its
// done paths (the records a lookup answers from), the range of each key component and the number
// of distinct unit cells of the key lattice they occupy. A unit cell is one "state" (state_key.hpp),
// so occupied cells / records says how much the records repeat each other.
#pragma once
#include <array>
#include <cstdint>

#include "database/store/library.hpp"

namespace grainbank::lookup {

struct KeyCoverage {
  std::int64_t records = 0;
  std::array<double, db::kKeySize> min{}, max{};  // key units; zero when there are no records
  std::int64_t occupied_cells = 0;                // distinct floor(key) over all records
};

KeyCoverage key_coverage(db::Library& library);

}  // namespace grainbank::lookup
