#include "mpm_solver/laws/law_registry.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>

namespace grainbank::mpm {

namespace {

// Built on first use: registrations run during static initialisation, in no defined order.
std::map<std::string_view, LawKind>& registry() {
  static std::map<std::string_view, LawKind> kinds;
  return kinds;
}

}  // namespace

LawRegistration::LawRegistration(LawKind kind) {
  if (!registry().emplace(kind.name, kind).second)
    throw std::logic_error("constitutive law \"" + std::string(kind.name) + "\" registered twice");
}

std::vector<LawKind> law_kinds() {
  std::vector<LawKind> kinds;
  for (const auto& [name, kind] : registry()) kinds.push_back(kind);
  return kinds;
}

std::optional<LawKind> find_law_kind(std::string_view name) {
  const auto it = registry().find(name);
  if (it == registry().end()) return std::nullopt;
  return it->second;
}

namespace {

std::string quoted_list(bool dem_backed_only) {
  std::vector<std::string_view> names;
  for (const LawKind& kind : law_kinds())
    if (kind.dem_backed || !dem_backed_only) names.push_back(kind.name);
  std::string out;
  for (std::size_t k = 0; k < names.size(); ++k)
    out += (k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + ("\"" + std::string(names[k]) + "\"");
  return out;
}

}  // namespace

std::string law_names() { return quoted_list(false); }
std::string dem_backed_law_names() { return quoted_list(true); }

std::unique_ptr<ConstitutiveLaw> read_law(const common::JsonNode& material, const LawContext& scene) {
  const common::JsonNode law = material.at("law", law_names());
  const std::optional<LawKind> kind = find_law_kind(law.string());
  if (!kind) law.fail_expected(law_names());
  material.allow_only(kind->keys);
  if (scene.ranks > 1 && !kind->runs_on_ranks)
    law.fail("law \"" + std::string(kind->name) + "\" cannot run on " + std::to_string(scene.ranks) +
             " MPI ranks (it is neither computed alike on every rank nor spread over them): run this scene without "
             "mpirun, on the threads of one process");
  return kind->read(material, scene);
}

}  // namespace grainbank::mpm
