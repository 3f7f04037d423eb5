#include "mpm_solver/app/laws_command.hpp"

#include "mpm_solver/laws/law_registry.hpp"

namespace grainbank::mpm::app {

nlohmann::json law_catalogue() {
  nlohmann::json laws = nlohmann::json::object();
  for (const LawKind& kind : law_kinds()) {
    nlohmann::json blocks = nlohmann::json::object();
    for (const KeyBlock& block : kind.blocks) blocks[std::string(block.name)] = block.keys;
    laws[std::string(kind.name)] = {{"keys", kind.keys}, {"blocks", blocks}, {"dem_backed", kind.dem_backed}};
  }
  return {{"laws", laws}};
}

void print_law_table(std::ostream& out) {
  for (const LawKind& kind : law_kinds()) {
    out << kind.name << (kind.dem_backed ? "  dem-backed  " : "  analytic  ");
    for (std::size_t k = 0; k < kind.keys.size(); ++k) out << (k ? ", " : "") << kind.keys[k];
    for (const KeyBlock& block : kind.blocks) {
      out << "; " << block.name << ": ";
      for (std::size_t k = 0; k < block.keys.size(); ++k) out << (k ? ", " : "") << block.keys[k];
    }
    out << '\n';
  }
}

}  // namespace grainbank::mpm::app
