/* The stop flag of an `evo` command that runs until stopped (`evo run`,
 * `evo serve`): SIGINT and SIGTERM set it, and a scene script stops with
 * it too (lua_evo.h, evo_lua_watch_stop). */
#ifndef EVO_CMD_STOP_H
#define EVO_CMD_STOP_H

#include <signal.h>

/* The signal that asked to stop; 0: none yet. */
extern volatile sig_atomic_t evo_cmd_stop_requested;

/* Catch SIGINT and SIGTERM into evo_cmd_stop_requested. */
void evo_cmd_catch_stop(void);

#endif
