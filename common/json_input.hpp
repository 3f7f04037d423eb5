// Reading JSON input files so that every error names the file, the JSON pointer of the offending
// value and what was expected, e.g.
//   cell.json: /material/k_n: expected a positive number, got -5
// No physics here: tools describe their schema with these readers and fill their own structs.
#pragma once
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <span>
#include <string_view>

namespace grainbank::common {

// The one exception type of input reading; what() is a complete one-line message.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An interval of accepted numbers and its wording in messages ("a positive number", "a number in
// (0, 1]"). Every Range also rejects NaN and infinities.
struct Range {
  double low = -std::numeric_limits<double>::infinity();
  double high = std::numeric_limits<double>::infinity();
  bool low_open = true, high_open = true;

  static Range any() { return {}; }
  static Range positive() { return {0, std::numeric_limits<double>::infinity(), true, true}; }
  static Range at_least(double low) { return {low, std::numeric_limits<double>::infinity(), false, true}; }
  // (low, high], [low, high], ... chosen by the flags.
  static Range between(double low, double high, bool low_open, bool high_open) {
    return {low, high, low_open, high_open};
  }

  bool contains(double v) const;
  std::string describe() const;  // "a positive number", "a number >= 1", "a number in (0, 1]"
};

// Reads the whole file and parses it. Throws InputError naming the file (and line and column for a
// syntax error) when the file cannot be read or is not JSON.
nlohmann::json load_json_file(const std::filesystem::path& file);

// A value inside a loaded document together with where it is: the file name used in messages and
// its JSON pointer ("" for the root). Cheap to copy; refers to the document, which must outlive it.
class JsonNode {
 public:
  JsonNode(const nlohmann::json& value, std::string file, std::string pointer = "");

  const nlohmann::json& value() const { return *value_; }
  const std::string& file() const { return file_; }
  const std::string& pointer() const { return pointer_; }

  // Objects. `at` requires the key (the message says what was expected there); `find` does not.
  JsonNode at(std::string_view key, std::string_view expected) const;
  std::optional<JsonNode> find(std::string_view key) const;
  bool has(std::string_view key) const;
  // Rejects any key not in `allowed`, listing the allowed ones.
  void allow_only(std::initializer_list<std::string_view> allowed) const;
  void allow_only(std::span<const std::string_view> allowed) const;

  // Arrays.
  std::size_t array_size(std::string_view expected = "an array") const;
  JsonNode at(std::size_t index) const;

  // Typed values; each throws InputError on a wrong type or a value outside the range.
  double number(const Range& range = Range::any()) const;
  std::int64_t integer(std::int64_t min, std::int64_t max = std::numeric_limits<std::int64_t>::max()) const;
  bool boolean() const;
  std::string string() const;
  void require_object() const;

  // Shorthands for fields of this object: required, or optional with a default.
  double number(std::string_view key, const Range& range) const;
  double number_or(std::string_view key, double fallback, const Range& range) const;
  std::int64_t integer_or(std::string_view key, std::int64_t fallback, std::int64_t min,
                          std::int64_t max = std::numeric_limits<std::int64_t>::max()) const;
  bool boolean_or(std::string_view key, bool fallback) const;

  // Throws "FILE: POINTER: expected EXPECTED, got <this value>".
  [[noreturn]] void fail_expected(std::string_view expected) const;
  // Throws "FILE: POINTER/KEY: required field missing; expected EXPECTED".
  [[noreturn]] void fail_missing(std::string_view key, std::string_view expected) const;
  // Throws "FILE: POINTER: MESSAGE" for checks that involve several values.
  [[noreturn]] void fail(std::string_view message) const;

 private:
  const nlohmann::json* value_;
  std::string file_, pointer_;
};

// Runs a constructor that validates its own arguments and turns its std::invalid_argument into an
// InputError at `node`, so a physics-level refusal still names the file and the JSON pointer.
template <class Make>
auto at_node(const JsonNode& node, Make&& make) -> decltype(make()) {
  try {
    return make();
  } catch (const std::invalid_argument& e) {
    node.fail(e.what());
  }
}

// "a string (\"abc\")", "-5", "an array", "null": how a value is quoted after "got".
std::string describe_value(const nlohmann::json& value);

}  // namespace grainbank::common
