#include "common/json_input.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

namespace grainbank::common {
namespace {

// JSON pointer escaping (RFC 6901): "~" -> "~0", "/" -> "~1".
std::string escaped(std::string_view key) {
  std::string out;
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

std::string shortest(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  std::string text = s.str();
  // Prefer the short form when it round-trips (so 0.1 prints as 0.1, not 0.10000000000000001).
  std::ostringstream brief;
  brief << v;
  return std::stod(brief.str()) == v ? brief.str() : text;
}

// nlohmann reports the byte offset where parsing stopped; people want a line and a column.
std::string line_and_column(const std::string& text, std::size_t byte) {
  std::size_t line = 1, column = 1;
  for (std::size_t k = 0; k + 1 < byte && k < text.size(); ++k) {
    if (text[k] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// Byte offset of the first occurrence of `token` outside JSON strings, or text.size(). nlohmann reports
// a number too large for a double (1e999) without a position, but the token is in its message.
std::size_t offset_outside_strings(const std::string& text, const std::string& token) {
  bool in_string = false;
  for (std::size_t k = 0; k < text.size(); ++k) {
    if (in_string) {
      if (text[k] == '\\') ++k;
      else if (text[k] == '"') in_string = false;
    } else if (text[k] == '"') {
      in_string = true;
    } else if (!token.empty() && text.compare(k, token.size(), token) == 0) {
      return k;
    }
  }
  return text.size();
}

// The part of nlohmann's message after its "[json.exception...] parse error at ...: " prefix.
std::string parse_detail(const std::string& what) {
  const std::size_t at = what.find("parse error");
  const std::size_t colon = what.find(": ", at == std::string::npos ? 0 : at);
  return colon == std::string::npos ? what : what.substr(colon + 2);
}

}  // namespace

bool Range::contains(double v) const {
  if (!std::isfinite(v)) return false;
  const bool above = low_open ? v > low : v >= low;
  const bool below = high_open ? v < high : v <= high;
  return above && below;
}

std::string Range::describe() const {
  const bool no_low = std::isinf(low), no_high = std::isinf(high);
  if (no_low && no_high) return "a finite number";
  if (no_high) {
    if (low == 0 && low_open) return "a positive number";
    return std::string("a number ") + (low_open ? "> " : ">= ") + shortest(low);
  }
  if (no_low) return std::string("a number ") + (high_open ? "< " : "<= ") + shortest(high);
  return "a number in " + std::string(low_open ? "(" : "[") + shortest(low) + ", " + shortest(high) +
         (high_open ? ")" : "]");
}

nlohmann::json load_json_file(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(name + ": cannot open the file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(name + ": " + line_and_column(text, e.byte) + ": malformed JSON: " + parse_detail(e.what()));
  } catch (const nlohmann::json::exception& e) {  // e.g. a number too large for a double (1e999)
    std::string detail = e.what();
    if (const std::size_t bracket = detail.find("] "); bracket != std::string::npos) detail.erase(0, bracket + 2);
    std::string where;
    if (const std::size_t open = detail.find('\''), close = detail.rfind('\''); open < close && close != std::string::npos)
      if (const std::size_t at = offset_outside_strings(text, detail.substr(open + 1, close - open - 1)); at < text.size())
        where = line_and_column(text, at + 1) + ": ";
    throw InputError(name + ": " + where + "malformed JSON: " + detail);
  }
}

std::string describe_value(const nlohmann::json& v) {
  switch (v.type()) {
    case nlohmann::json::value_t::null: return "null";
    case nlohmann::json::value_t::boolean: return v.get<bool>() ? "true" : "false";
    case nlohmann::json::value_t::string: return "a string (" + v.dump() + ")";
    case nlohmann::json::value_t::array:
      if (v.empty()) return "an empty array";
      return "an array of " + std::to_string(v.size()) + (v.size() == 1 ? " entry" : " entries");
    case nlohmann::json::value_t::object: return "an object";
    case nlohmann::json::value_t::number_float: return shortest(v.get<double>());
    default: return v.dump();
  }
}

JsonNode::JsonNode(const nlohmann::json& value, std::string file, std::string pointer)
    : value_(&value), file_(std::move(file)), pointer_(std::move(pointer)) {}

void JsonNode::fail(std::string_view message) const {
  throw InputError(file_ + ": " + (pointer_.empty() ? "/" : pointer_) + ": " + std::string(message));
}

void JsonNode::fail_expected(std::string_view expected) const {
  fail("expected " + std::string(expected) + ", got " + describe_value(*value_));
}

void JsonNode::require_object() const {
  if (!value_->is_object()) fail_expected("an object");
}

std::optional<JsonNode> JsonNode::find(std::string_view key) const {
  require_object();
  const auto it = value_->find(key);
  if (it == value_->end()) return std::nullopt;
  return JsonNode(*it, file_, pointer_ + "/" + escaped(key));
}

bool JsonNode::has(std::string_view key) const { return find(key).has_value(); }

void JsonNode::fail_missing(std::string_view key, std::string_view expected) const {
  throw InputError(file_ + ": " + pointer_ + "/" + escaped(key) + ": required field missing; expected " +
                   std::string(expected));
}

JsonNode JsonNode::at(std::string_view key, std::string_view expected) const {
  if (auto child = find(key)) return *child;
  fail_missing(key, expected);
}

void JsonNode::allow_only(std::initializer_list<std::string_view> allowed) const {
  allow_only(std::span<const std::string_view>(allowed.begin(), allowed.size()));
}

void JsonNode::allow_only(std::span<const std::string_view> allowed) const {
  require_object();
  for (const auto& item : value_->items()) {
    bool known = false;
    for (std::string_view a : allowed) known = known || item.key() == a;
    if (known) continue;
    std::string list;
    for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    throw InputError(file_ + ": " + pointer_ + "/" + escaped(item.key()) + ": unknown key; allowed keys here: " + list);
  }
}

std::size_t JsonNode::array_size(std::string_view expected) const {
  if (!value_->is_array()) fail_expected(expected);
  return value_->size();
}

JsonNode JsonNode::at(std::size_t index) const {
  if (!value_->is_array() || index >= value_->size())
    fail_expected("an array with at least " + std::to_string(index + 1) + " entries");
  return JsonNode((*value_)[index], file_, pointer_ + "/" + std::to_string(index));
}

double JsonNode::number(const Range& range) const {
  if (!value_->is_number()) fail_expected(range.describe());
  const double v = value_->get<double>();
  if (!range.contains(v)) fail_expected(range.describe());
  return v;
}

std::int64_t JsonNode::integer(std::int64_t min, std::int64_t max) const {
  std::string expected = "an integer";
  if (max == std::numeric_limits<std::int64_t>::max()) expected += " >= " + std::to_string(min);
  else expected += " in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  if (value_->is_number_unsigned()) {
    const auto v = value_->get<std::uint64_t>();
    if (v > static_cast<std::uint64_t>(max) || static_cast<std::int64_t>(v) < min) fail_expected(expected);
    return static_cast<std::int64_t>(v);
  }
  if (value_->is_number_integer()) {
    const auto v = value_->get<std::int64_t>();
    if (v < min || v > max) fail_expected(expected);
    return v;
  }
  // 125.0 or 1e3 are integers too, as long as they are exact.
  if (value_->is_number_float()) {
    const double v = value_->get<double>();
    if (std::isfinite(v) && v == std::floor(v) && v >= static_cast<double>(min) && v <= static_cast<double>(max))
      return static_cast<std::int64_t>(v);
  }
  fail_expected(expected);
}

bool JsonNode::boolean() const {
  if (!value_->is_boolean()) fail_expected("true or false");
  return value_->get<bool>();
}

std::string JsonNode::string() const {
  if (!value_->is_string()) fail_expected("a string");
  return value_->get<std::string>();
}

double JsonNode::number(std::string_view key, const Range& range) const {
  return at(key, range.describe()).number(range);
}

double JsonNode::number_or(std::string_view key, double fallback, const Range& range) const {
  const auto child = find(key);
  return child ? child->number(range) : fallback;
}

std::int64_t JsonNode::integer_or(std::string_view key, std::int64_t fallback, std::int64_t min,
                                  std::int64_t max) const {
  const auto child = find(key);
  return child ? child->integer(min, max) : fallback;
}

bool JsonNode::boolean_or(std::string_view key, bool fallback) const {
  const auto child = find(key);
  return child ? child->boolean() : fallback;
}

}  // namespace grainbank::common
