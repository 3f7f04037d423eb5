#include "dem_sampler/app/test_stop_point.hpp"

#include <csignal>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace grainbank::app {
namespace {
constexpr const char* kVariable = "GRAINBANK_TEST_STOP_AFTER_RECORDS";
}  // namespace

TestStopPoint::TestStopPoint() {
  const char* value = std::getenv(kVariable);
  if (!value) return;
  const std::string text(value);
  std::size_t used = 0;
  try {
    stop_after_ = std::stol(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || *stop_after_ < 0)
    throw std::invalid_argument(std::string(kVariable) + "=\"" + text + "\": expected a count of records (0 or more)");
}

void TestStopPoint::committed(long records) {
  records_ += records;
  if (!stop_after_ || records_ < *stop_after_) return;
  stop_after_.reset();
  std::raise(SIGSTOP);
}

}  // namespace grainbank::app
