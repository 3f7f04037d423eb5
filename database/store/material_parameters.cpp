#include "database/store/material_parameters.hpp"

#include <bit>
#include <cstdint>
#include <cstdio>
#include <charconv>
#include <sstream>
#include <type_traits>
#include <utility>
#include <stdexcept>

namespace grainbank::db {
namespace {

// The single list of parameters: JSON, hash and differences all walk it, so none can forget one.
template <class M, class Visit>
void visit_parameters(M& m, Visit visit) {
  visit("density", m.density);
  visit("contact.k_n", m.contact.k_n);
  visit("contact.k_t", m.contact.k_t);
  visit("contact.restitution", m.contact.restitution);
  visit("contact.friction", m.contact.friction);
  visit("contact.contact_weight", m.contact.contact_weight);
  visit("bond.tensile_strength", m.bond.tensile_strength);
  visit("bond.shear_strength", m.bond.shear_strength);
  visit("bond.exponent", m.bond.exponent);
  visit("bond.bonding_distance", m.bond.bonding_distance);
  visit("rolling.stiffness", m.rolling.stiffness);
  visit("rolling.friction", m.rolling.friction);
  visit("effects.bonds", m.effects.bonds);
  visit("effects.kinetic_stress", m.effects.kinetic_stress);
  visit("effects.rolling", m.effects.rolling);
}

// Parameters added after libraries were first written, each with the value every older library has:
// absent from a catalogue means that value, and at that value they are left out of the JSON and the
// hash, so older libraries keep their identity.
template <class M, class Visit>
void visit_later_parameters(M& m, Visit visit) {
  visit("bond.softening", m.bond.softening, 0.0);
}

nlohmann::json::json_pointer pointer(const std::string& dotted) {
  std::string path = "/" + dotted;
  for (char& c : path)
    if (c == '.') c = '/';
  return nlohmann::json::json_pointer(path);
}

std::uint64_t fnv1a(const void* data, std::size_t size, std::uint64_t hash = 14695981039346656037ull) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t k = 0; k < size; ++k) hash = (hash ^ bytes[k]) * 1099511628211ull;
  return hash;
}

std::string hex16(std::uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

// Shortest text that reads back to the same value: 0.2, not 0.20000000000000001.
template <class T>
std::string to_text(const T& value) {
  if constexpr (std::is_floating_point_v<T>) {
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, value).ptr;
    return std::string(text, end);
  } else {
    std::ostringstream out;
    out << std::boolalpha << value;
    return out.str();
  }
}

}  // namespace

nlohmann::json material_to_json(const dem::Material& material) {
  nlohmann::json json = nlohmann::json::object();
  visit_parameters(material, [&](const char* name, const auto& value) { json[pointer(name)] = value; });
  visit_later_parameters(material, [&](const char* name, const auto& value, const auto& older) {
    if (value != older) json[pointer(name)] = value;
  });
  return json;
}

dem::Material material_from_json(const nlohmann::json& json) {
  dem::Material material;
  visit_parameters(material, [&](const char* name, auto& value) {
    const auto p = pointer(name);
    if (!json.contains(p)) throw std::invalid_argument(std::string("material: missing parameter ") + name);
    value = json.at(p).get<std::remove_reference_t<decltype(value)>>();
  });
  visit_later_parameters(material, [&](const char* name, auto& value, const auto& older) {
    const auto p = pointer(name);
    value = json.contains(p) ? json.at(p).get<std::remove_reference_t<decltype(value)>>() : older;
  });
  return material;
}

std::string parameter_hash(const dem::Material& material) {
  std::uint64_t hash = fnv1a("grainbank-material-v1", 21);
  const auto add = [&](const char* name, const auto& value) {
    hash = fnv1a(name, std::char_traits<char>::length(name), hash);
    const double as_double = static_cast<double>(value);
    const auto bits = std::bit_cast<std::uint64_t>(as_double);
    hash = fnv1a(&bits, sizeof bits, hash);
  };
  visit_parameters(material, add);
  visit_later_parameters(material, [&](const char* name, const auto& value, const auto& older) {
    if (value != older) add(name, value);
  });
  return hex16(hash);
}

namespace {

// Every parameter, later ones included, as (name, shortest text), in the lists' order.
std::vector<std::pair<std::string, std::string>> named_texts(const dem::Material& material) {
  std::vector<std::pair<std::string, std::string>> texts;
  const auto add = [&](const char* name, const auto& value) { texts.emplace_back(name, to_text(value)); };
  visit_parameters(material, add);
  visit_later_parameters(material, [&](const char* name, const auto& value, const auto&) { add(name, value); });
  return texts;
}

}  // namespace

std::vector<std::string> material_differences(const dem::Material& library, const dem::Material& given) {
  const auto library_texts = named_texts(library), given_texts = named_texts(given);
  std::vector<std::string> differences;
  for (std::size_t k = 0; k < library_texts.size(); ++k)
    if (library_texts[k].second != given_texts[k].second)
      differences.push_back(library_texts[k].first + ": library " + library_texts[k].second + ", given " +
                            given_texts[k].second);
  return differences;
}

std::string text_hash(const std::string& text) { return hex16(fnv1a(text.data(), text.size())); }

}  // namespace grainbank::db
