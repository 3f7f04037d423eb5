// `mpm_solver laws`: the constitutive laws a scene can name, with the keys each material object
// accepts, from the law registry. Scripts ask this instead of keeping their own copy:
//   {"laws": {"elastic": {"keys": ["name", "law", "density", ...], "dem_backed": false}, ...}}
#pragma once
#include <nlohmann/json.hpp>
#include <ostream>

namespace grainbank::mpm::app {

nlohmann::json law_catalogue();
// One line per law: its name, "dem-backed" or "analytic", and its keys.
void print_law_table(std::ostream& out);

}  // namespace grainbank::mpm::app
