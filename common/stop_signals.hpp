// SIGINT / SIGTERM as a request to stop: the handler only raises a flag, which long-running commands
// (`dem_sampler sample` after every record, `mpm_solver` after every step) poll, so they can leave
// their files consistent — no path left `running`, a restart file written — before exiting.
#pragma once
#include <atomic>

namespace grainbank::common {

// Installs the handlers (once) and returns the flag they raise.
const std::atomic<bool>& install_stop_signals();
// The signal that raised the flag, 0 if none.
int stop_signal();

}  // namespace grainbank::common
