// Table rows for input-error tests: a file's text and the pieces its error message must contain
// (the JSON path or line, and the expected value), besides the file name.
#pragma once
#include <gtest/gtest.h>

#include <ostream>
#include <string>
#include <vector>

namespace grainbank::testing {

struct ErrorCase {
  std::string name;                   // test name suffix
  std::string text;                   // file contents
  std::vector<std::string> expected;  // substrings of the message
};

inline std::ostream& operator<<(std::ostream& out, const ErrorCase& c) { return out << c.name; }

inline std::string case_name(const ::testing::TestParamInfo<ErrorCase>& info) { return info.param.name; }

// Runs `load` and checks that it throws E with a message naming `file` and every expected piece.
template <class E, class Load>
void expect_input_error(Load&& load, const std::string& file, const std::vector<std::string>& expected) {
  try {
    load();
    FAIL() << "no error for " << file;
  } catch (const E& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(file), std::string::npos) << message;
    for (const std::string& piece : expected) EXPECT_NE(message.find(piece), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
  }
}

}  // namespace grainbank::testing
