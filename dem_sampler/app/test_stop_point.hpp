// A pause for tests of concurrent and interrupted samplers, so they never race the sampler's speed.
// With GRAINBANK_TEST_STOP_AFTER_RECORDS=N in its environment, `dem_sampler sample` stops itself
// (SIGSTOP) once, as soon as it holds the sampler lock and has committed at least N records of this
// run (N = 0: right after taking the lock and registering its paths). The test waits for the stop
// (waitpid with WUNTRACED), acts on a library whose lock is certainly held and whose run is certainly
// unfinished, then continues the sampler (SIGCONT) or kills it. Without the variable nothing happens.
#pragma once
#include <optional>

namespace grainbank::app {

class TestStopPoint {
 public:
  // Reads the variable; throws std::invalid_argument naming it when it is not a count of records.
  TestStopPoint();
  // Adds `records` just committed (0 when only the lock is taken) and stops once the count is reached.
  void committed(long records);

 private:
  std::optional<long> stop_after_;
  long records_ = 0;
};

}  // namespace grainbank::app
