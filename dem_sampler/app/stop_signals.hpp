// SIGINT / SIGTERM as a request to stop: the handler only raises a flag, which the sampler polls
// after every record, so the catalogue is left consistent (no path stays `running`).
#pragma once
#include <atomic>

namespace grainbank::app {

// Installs the handlers (once) and returns the flag they raise.
const std::atomic<bool>& install_stop_signals();
// The signal that raised the flag, 0 if none.
int stop_signal();

}  // namespace grainbank::app
