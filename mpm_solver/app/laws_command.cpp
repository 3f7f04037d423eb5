#include "mpm_solver/app/laws_command.hpp"

#include "mpm_solver/laws/law_registry.hpp"

namespace grainbank::mpm::app {

nlohmann::json law_catalogue() {
  nlohmann::json laws = nlohmann::json::object();
  for (const LawKind& kind : law_kinds()) {
    nlohmann::json keys = nlohmann::json::array();
    for (std::string_view key : kind.keys) keys.push_back(key);
    laws[std::string(kind.name)] = {{"keys", keys}, {"dem_backed", kind.dem_backed}};
  }
  return {{"laws", laws}};
}

void print_law_table(std::ostream& out) {
  for (const LawKind& kind : law_kinds()) {
    out << kind.name << (kind.dem_backed ? "  dem-backed  " : "  analytic  ");
    for (std::size_t k = 0; k < kind.keys.size(); ++k) out << (k ? ", " : "") << kind.keys[k];
    out << '\n';
  }
}

}  // namespace grainbank::mpm::app
