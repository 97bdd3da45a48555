/* Private to src/cli. SIGINT / SIGTERM in a command that writes files (issue 27's audit):
 * the default action killed `generate` half-way through its OBJ and left OUT.obj.tmp.PID
 * (98 MB). A command registers the outputs it will write (outputs_ready does); on the
 * signal the handler removes, with async-signal-safe calls only, their temporary files
 * (atomic_file.c's PATH.tmp.PID, output_set.c's PATH.staged.PID) and the outputs this call
 * already renamed into place, says so and exits 128 + the signal: exit != 0 leaves nothing.
 * `restir render` keeps its own first-signal handling (stop.h) and uses only the temporary
 * file removal on its second signal. */
#ifndef RESTIR_SRC_CLI_SIGNAL_CLEANUP_H
#define RESTIR_SRC_CLI_SIGNAL_CLEANUP_H

/* Remembers path (an output this call will write) and what is there now; at most 40. */
void cleanup_register(const char *path);
/* Installs the SIGINT / SIGTERM handler above; `command` names it in the message. */
void cleanup_install(const char *command);
/* Async-signal-safe: removes the temporary files of the registered outputs. */
void cleanup_remove_temps(void);

#endif
