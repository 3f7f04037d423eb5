#include "database/celldb/query_command.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "database/lookup/lookup_index.hpp"
#include "database/store/library.hpp"

namespace grainbank::celldb {
namespace {

dem::Mat3 matrix_from_json(const nlohmann::json& json, const std::string& where, const dem::Mat3& fill) {
  const auto fail = [&] { return std::invalid_argument(where + ": expected a 2x2 or 3x3 array of numbers, got " + json.dump()); };
  if (!json.is_array() || (json.size() != 2 && json.size() != 3)) throw fail();
  const std::size_t n = json.size();
  dem::Mat3 m = fill;
  for (std::size_t i = 0; i < n; ++i) {
    if (!json[i].is_array() || json[i].size() != n) throw fail();
    for (std::size_t j = 0; j < n; ++j) {
      if (!json[i][j].is_number()) throw fail();
      m(static_cast<int>(i), static_cast<int>(j)) = json[i][j].get<double>();
    }
  }
  return m;
}

std::string read_state_text(const std::string& state) {
  if (state.find_first_not_of(" \t\n") != std::string::npos && state[state.find_first_not_of(" \t\n")] == '{')
    return state;
  std::ifstream in(state);
  if (!in) throw std::invalid_argument("--state: neither JSON text nor a readable file: " + state);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

nlohmann::json matrix_json(const dem::Mat3& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) rows.push_back({m(i, 0), m(i, 1), m(i, 2)});
  return rows;
}

}  // namespace

lookup::LookupState lookup_state_from_json(const nlohmann::json& json, const std::string& source) {
  if (!json.is_object()) throw std::invalid_argument(source + ": expected an object with F, L and D");
  for (const auto& item : json.items())
    if (item.key() != "F" && item.key() != "L" && item.key() != "D")
      throw std::invalid_argument(source + ": /" + item.key() + ": unknown key; allowed keys here: F, L, D");
  if (!json.contains("F")) throw std::invalid_argument(source + ": /F: missing (the deformation gradient)");
  lookup::LookupState state;
  state.F = matrix_from_json(json["F"], source + ": /F", dem::Mat3::Identity());
  if (!(state.F.determinant() > 0)) throw std::invalid_argument(source + ": /F: expected det F > 0");
  if (json.contains("L")) state.L = matrix_from_json(json["L"], source + ": /L", dem::Mat3::Zero());
  if (json.contains("D")) {
    if (!json["D"].is_number()) throw std::invalid_argument(source + ": /D: expected a number, got " + json["D"].dump());
    state.damage = json["D"].get<double>();
  }
  return state;
}

nlohmann::json query_library(const QueryOptions& options) {
  const std::string text = read_state_text(options.state);
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::invalid_argument("--state: not valid JSON: " + std::string(e.what()));
  }
  const lookup::LookupState state = lookup_state_from_json(json, "--state");
  db::Library library = db::Library::open(options.library);
  lookup::LookupIndex index(library.key_scales());
  index.refresh(library);
  const lookup::LookupAnswer a = index.query(state, options.lookup);
  nlohmann::json out = {{"stress", matrix_json(a.stress)},
                        {"stress_sign", "tension-positive"},
                        {"distance", a.neighbours ? nlohmann::json(a.distance) : nlohmann::json(nullptr)},
                        {"hit", a.hit},
                        {"tolerance", options.lookup.tolerance},
                        {"estimated_error", a.estimated_error},
                        {"neighbours", a.neighbours},
                        {"records", index.size()}};
  if (a.neighbours) out["nearest"] = {{"path", a.nearest.path_id}, {"record", a.nearest.record_index}};
  return out;
}

int run_query(const QueryOptions& options, std::ostream& out) {
  const nlohmann::json a = query_library(options);
  if (options.json) {
    out << a.dump(2) << "\n";
    return 0;
  }
  if (a["neighbours"] == 0) {
    out << "no records to answer from: the library has no done path\n";
    return 1;
  }
  out << "stress [Pa]     " << a["stress"].dump() << " (tension-positive)\n"
      << "distance        " << a["distance"].get<double>() << " (key units, nearest of " << a["neighbours"]
      << " neighbours: path " << a["nearest"]["path"] << " record " << a["nearest"]["record"] << ")\n"
      << "hit             " << (a["hit"].get<bool>() ? "yes" : "no") << " (tolerance " << a["tolerance"].get<double>()
      << ")\n"
      << "estimated error " << a["estimated_error"].get<double>() << " Pa\n";
  return 0;
}

}  // namespace grainbank::celldb
