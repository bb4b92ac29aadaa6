/* The stop flag of `evo run` and `evo serve` (cmd/stop.h). */
#define _POSIX_C_SOURCE 200809L
#include "cmd/stop.h"

#include <string.h>

#include "lua/lua_evo.h"

volatile sig_atomic_t evo_cmd_stop_requested;

static void on_signal(int sig)
{
	evo_cmd_stop_requested = sig;
}

void evo_cmd_catch_stop(void)
{
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
	evo_lua_watch_stop(&evo_cmd_stop_requested);
}
