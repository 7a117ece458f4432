// Graceful stop of `kanesens run` on SIGINT / SIGTERM (Ctrl-C, `kill`, Slurm's scancel, mpirun
// forwarding a SIGTERM). The handler only stores the signal number in a volatile sig_atomic_t
// (async-signal-safe); the ensemble loop polls stop_signal() between samples, stops claiming
// work, lets the in-flight sample finish and be written, closes the file collectively and
// reports how to --resume. A second signal of the same kind while stopping restores the
// default action and re-raises it (an impatient second Ctrl-C still kills at once; the file
// stays resumable, as after kill -9).
#pragma once

namespace kanesens::parallel {

// Installs the handlers for SIGINT and SIGTERM (idempotent; sigaction, SA_RESTART), and
// ignores SIGXFSZ (a write past `ulimit -f` then fails with EFBIG and is reported).
void install_stop_handlers();
// 0, or the number of the first stop signal received.
int stop_signal();
// "SIGINT", "SIGTERM" or "signal N".
const char* signal_name(int sig);

}  // namespace kanesens::parallel
