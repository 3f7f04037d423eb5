// SIGINT / SIGTERM as a request to stop: the handler only raises a flag, which long-running commands
// (`dem_sampler sample` after every record, `mpm_solver` after every step) poll, so they can leave
// their files consistent — no path left `running`, a restart file written — before exiting.
// SIGHUP (the terminal closed) and SIGPIPE (whoever read the progress lines is gone, e.g. a study
// killed outright) are requests to stop too: by default either ends the process at once, and with it
// the checkpoint it would have written (stop 86: a study killed by SIGKILL lost its run's). A write to
// a reader that is gone then fails quietly instead.
#pragma once
#include <atomic>

namespace grainbank::common {

// Installs the handlers (once) and returns the flag they raise.
const std::atomic<bool>& install_stop_signals();
// The signal that raised the flag, 0 if none.
int stop_signal();

}  // namespace grainbank::common
