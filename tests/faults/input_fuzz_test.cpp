// Bounded random-mutation fuzzing of the JSON loaders (cell.json, path.json, PATHS.json, scene JSON):
// from a valid document, a fixed-seed generator derives thousands of broken ones — values of the
// wrong type, NaN/inf spellings, out-of-range and huge numbers, deleted and unknown keys, moved
// subtrees, truncated or corrupted text. Every one either loads or throws common::InputError whose
// one-line message names the file and a location in it (a JSON pointer, or a line and column for a
// syntax error). Any other exception type, or a message without a location, is a failure.
#include <gtest/gtest.h>

#include <functional>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include "dem_sampler/driver/cell_input.hpp"
#include "common/json_input.hpp"
#include "common/temporary_directory.hpp"
#include "tests/faults/good_inputs.hpp"
#include "mpm_solver/io/scene_input.hpp"
#include "dem_sampler/driver/path_input.hpp"
#include "dem_sampler/sampler/paths_input.hpp"

namespace grainbank {
namespace {

using nlohmann::json;
using namespace faults;

// Replacement values: wrong types, NaN/inf look-alikes, zero, negatives, tiny, huge and integer limits.
const std::vector<json>& value_pool() {
  static const std::vector<json> pool = {
      0, -1, 1, 3, 2.5, -2.5, 1e-300, -1e-300, 1e300, -1e300, 1e9, 100000, 1e-7,
      json(9223372036854775807LL), json(std::numeric_limits<std::int64_t>::min()), json(18446744073709551615ULL),
      9.3e18, 9223372036854775808.0, true, false, nullptr, "NaN", "inf", "", "x", json::array(), json::object(),
      json::array({1, 2}), json::array({1, 2, 3}), json::array({json::array({1, 2}), json::array({3, 4})}),
      json::object({{"a", 1}})};
  return pool;
}

// Spellings JSON does not allow, or numbers beyond a double, put in the text in place of a number.
const std::vector<std::string> kBadNumbers = {"NaN", "nan", "Infinity", "-Infinity", "1e999", "-1e999", "1e-999",
                                              "0x10", "+1", ".5", "1.", "01", "1e", "--1", "1e+400"};

std::vector<json::json_pointer> all_pointers(const json& v, const json::json_pointer& at = json::json_pointer()) {
  std::vector<json::json_pointer> out{at};
  if (v.is_object())
    for (const auto& item : v.items())
      for (auto& p : all_pointers(item.value(), at / item.key())) out.push_back(std::move(p));
  if (v.is_array())
    for (std::size_t k = 0; k < v.size(); ++k)
      for (auto& p : all_pointers(v[k], at / k)) out.push_back(std::move(p));
  return out;
}

class Mutator {
 public:
  explicit Mutator(std::uint64_t seed) : random_(seed) {}

  // A document derived from `good` by one to three tree edits, then perhaps one text edit.
  std::string mutate(const json& good) {
    json doc = good;
    for (std::size_t edits = 1 + pick(3); edits > 0; --edits) edit_tree(doc);
    std::string text = doc.dump(pick(2) ? 2 : -1);
    if (pick(4) == 0) edit_text(text);
    return text;
  }

 private:
  std::size_t pick(std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(random_); }

  void edit_tree(json& doc) {
    const auto pointers = all_pointers(doc);
    const json::json_pointer at = pointers[pick(pointers.size())];
    json& node = doc[at];
    switch (pick(6)) {
      case 0: node = value_pool()[pick(value_pool().size())]; break;
      case 1:  // delete the key or entry
        if (!at.empty()) {
          json& parent = doc[at.parent_pointer()];
          if (parent.is_object()) parent.erase(at.back());
          else parent.erase(static_cast<std::size_t>(std::stoul(at.back())));
        }
        break;
      case 2:  // an unknown key (or an object where another type belongs)
        if (node.is_object()) node["unknown_key"] = 1;
        else node = json::object({{"unknown_key", 1}});
        break;
      case 3:  // scale or shift a number
        if (node.is_number()) {
          static const double factors[] = {-1, 0, 1e-12, 1e12, 0.5, 2, 1 + 1e-15};
          node = node.get<double>() * factors[pick(7)] + (pick(4) == 0 ? 1 : 0);
        } else {
          node = -1;
        }
        break;
      case 4: node = doc[pointers[pick(pointers.size())]]; break;  // a subtree from elsewhere
      default:  // grow or empty an array
        if (node.is_array() && !node.empty()) {
          if (pick(2)) node.push_back(node.back());
          else node = json::array();
        } else {
          node = json::array({node});
        }
    }
  }

  void edit_text(std::string& text) {
    switch (pick(4)) {
      case 0: text.resize(pick(text.size() + 1)); break;  // truncated file
      case 1: text.erase(pick(text.size()), 1); break;
      case 2: text.insert(pick(text.size() + 1), 1, static_cast<char>(pick(256))); break;  // any byte
      default: {  // a number replaced by a spelling that is not a JSON number
        static const std::regex number(R"(-?\d+(\.\d+)?([eE][-+]?\d+)?)");
        std::vector<std::pair<std::size_t, std::size_t>> spans;
        for (auto it = std::sregex_iterator(text.begin(), text.end(), number); it != std::sregex_iterator(); ++it)
          spans.emplace_back(it->position(), it->length());
        if (spans.empty()) return;
        const auto [at, length] = spans[pick(spans.size())];
        text.replace(at, length, kBadNumbers[pick(kBadNumbers.size())]);
      }
    }
  }

  std::mt19937_64 random_;
};

struct Loader {
  const char* file_name;
  const char* good;
  std::function<void(const std::filesystem::path&)> load;
};

// Runs `count` mutations of the loader's good document; returns the failures (at most 10 kept).
std::vector<std::string> fuzz(const Loader& loader, int count, std::uint64_t seed, int& loaded) {
  const TemporaryDirectory dir("gb-fuzz");
  const json good = json::parse(loader.good);
  // "file: /pointer: ..." or "file: line L, column C: ...", on one line.
  const std::regex located(std::string("^(.*/)?") + loader.file_name + R"(: (/\S*|line \d+, column \d+): [^\n]+$)");
  Mutator mutator(seed);
  std::vector<std::string> failures;
  loaded = 0;
  for (int k = 0; k < count; ++k) {
    const std::string text = mutator.mutate(good);
    const auto file = dir.write(loader.file_name, text);
    std::string problem;
    try {
      loader.load(file);
      ++loaded;
    } catch (const common::InputError& e) {
      if (!std::regex_match(e.what(), located)) problem = std::string("message without file and location: ") + e.what();
    } catch (const std::exception& e) {
      problem = std::string("not an InputError (") + typeid(e).name() + "): " + e.what();
    }
    if (!problem.empty() && failures.size() < 10) failures.push_back("mutation " + std::to_string(k) + ": " + problem + "\n  input: " + text);
  }
  return failures;
}

void expect_only_input_errors(const Loader& loader, int count) {
  const TemporaryDirectory dir("gb-fuzz-good");
  ASSERT_NO_THROW(loader.load(dir.write(loader.file_name, loader.good))) << "the unmutated " << loader.file_name;
  int loaded = 0;
  const auto failures = fuzz(loader, count, 20240611, loaded);
  for (const std::string& f : failures) ADD_FAILURE() << f;
  // The mutations must not all be rejected at the first byte, nor all be harmless.
  EXPECT_GT(loaded, 0) << "no mutation of " << loader.file_name << " loaded";
  EXPECT_LT(loaded, count / 2) << "most mutations of " << loader.file_name << " loaded: they test little";
}

TEST(InputFuzz, CellJsonLoadsOrThrowsInputErrorWithLocation) {
  expect_only_input_errors({"cell.json", kCell, [](const auto& f) { app::load_cell_input(f); }}, 3000);
}

TEST(InputFuzz, PathJsonLoadsOrThrowsInputErrorWithLocation) {
  expect_only_input_errors({"path.json", kPath, [](const auto& f) { app::load_path(f); }}, 3000);
}

TEST(InputFuzz, PathsJsonLoadsOrThrowsInputErrorWithLocation) {
  expect_only_input_errors({"paths.json", kPaths, [](const auto& f) { sampler::load_paths_file(f); }}, 3000);
}

TEST(InputFuzz, SceneJsonLoadsOrThrowsInputErrorWithLocation) {
  expect_only_input_errors({"scene.json", kScene, [](const auto& f) { mpm::io::load_scene(f); }}, 3000);
}

}  // namespace
}  // namespace grainbank
