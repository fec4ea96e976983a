#pragma once
// SIGINT and SIGTERM for the `surfreg` program: the handler only records the
// signal; long loops (solver iterations, sweep runs, measure stages) call
// ThrowIfInterrupted, whose exception unwinds to main, which removes the
// live temporary files, prints "surfreg: interrupted" and exits 128 + the
// signal (130 for SIGINT, 143 for SIGTERM). What is complete stays: written
// outputs, a sweep's partial file, align's --log rows so far.
//
// A second signal while the first is unwinding ends the process at once
// (for a stage that never checks), still removing the live temporaries:
// the handler does so with unlink(2) and _exit(2) only.
//
// Without InstallInterruptHandlers (tests, the Python module) nothing is
// ever interrupted and ThrowIfInterrupted never throws.
#include <csignal>
#include <string>

namespace surfreg {

// Thrown by ThrowIfInterrupted. Deliberately not a std::exception, so that
// no `catch (const std::exception&)` on the way turns it into an error.
class Interrupted {
 public:
  explicit Interrupted(int signal) : signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

// Installs the handlers for SIGINT and SIGTERM (once, in main), and ignores
// SIGXFSZ so that a write past a file-size limit fails (EFBIG) rather than
// killing the process.
void InstallInterruptHandlers();

// Throws Interrupted if a signal was received.
void ThrowIfInterrupted();

// The exit code for `signal`: 128 + signal.
int InterruptExitCode(int signal);

// Live temporary files (io/atomic_file.h and the GeoTIFF writer): each
// is registered from its creation until it is renamed or removed, so that
// an interrupted run leaves none. Returns a slot for UnregisterTemporary,
// or -1 when every slot is taken (the file is then not tracked; its own
// error paths still remove it).
int RegisterTemporary(const std::string& path);
void UnregisterTemporary(int slot);

// Removes every registered temporary file (main, after an Interrupted).
void RemoveTemporaries();

}  // namespace surfreg
