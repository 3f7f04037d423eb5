#include "mpm_solver/app/laws_command.hpp"

#include <span>
#include <string_view>

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

namespace {

void print_keys(std::ostream& out, std::span<const std::string_view> keys) {
  for (std::size_t k = 0; k < keys.size(); ++k) out << (k ? ", " : "") << keys[k];
}

}  // namespace

void print_law_table(std::ostream& out) {
  for (const LawKind& kind : law_kinds()) {
    out << kind.name << (kind.dem_backed ? "  dem-backed  " : "  analytic  ");
    print_keys(out, kind.keys);
    for (const KeyBlock& block : kind.blocks) {
      out << "; " << block.name << ": ";
      print_keys(out, block.keys);
    }
    out << '\n';
  }
}

}  // namespace grainbank::mpm::app
