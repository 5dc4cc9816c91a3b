#pragma once
// Ctrl-C and SIGTERM (issue #26: they left hidden .tmp- files and lost a long run's statistics).
// The CLI installs the handlers before any work. A signal then removes the temporary files of the
// outputs not yet committed (AtomicFile registers them) and ends the process as the signal would.
// A command that can stop cleanly between units of work (simulate, between steps) defers instead:
// the first signal is only noted, the command polls interrupt_signal() and ends its outputs itself;
// a second signal ends the process at once, as above.
namespace rbpart {

void install_interrupt_handlers();
void defer_interrupts(bool defer);
// The signal noted while deferred (SIGINT, SIGTERM), 0 if none.
int interrupt_signal();
// "SIGINT" / "SIGTERM".
const char* signal_name(int signal);

// Temporary files a signal removes. `path` must stay valid until unregistered. Returns a slot for
// unregister_temp_file, or -1 if every slot is taken (the file is then only removed by unwinding).
int register_temp_file(const char* path);
void unregister_temp_file(int slot);

}  // namespace rbpart
