/* Traces (docs/running.md, Traces): what a mind read and wrote, tick by
 * tick, as the Q15.16 integers it saw, with each skill's influence. A
 * header names the mind, its sensors, actuators and skills. DEMOSIM in one
 * process and a mind driving a remote simulator write the same lines, so
 * their traces compare byte for byte; the firmware replays them. */
#ifndef EVO_TRACE_H
#define EVO_TRACE_H

#include <stdio.h>

#include "evo/evo.h"
#include "mind/mindfolder.h"

void evo_trace_header(FILE *f, const evo_mindfolder *mind);

/* One tick's line. */
void evo_trace_tick(FILE *f, long tick, const evo_mind *m,
		    const evo_q16 *sensors, const evo_q16 *actuators,
		    const evo_state *state);

/* Version 3, of teams (docs/teams.md): after the line "evo-trace 3", one
 * block per team, "team NAME mind MIND names HASH bots N BOT..." and the
 * sensors, actuators and skills lines of version 2; then one line per bot
 * and tick, the tick, the bot's name, and the values of version 2. */
void evo_trace_team_header(FILE *f, const char *team,
			   const evo_mindfolder *mind, const char *const *bots,
			   int n_bots);
void evo_trace_tick_bot(FILE *f, long tick, const char *bot, const evo_mind *m,
			const evo_q16 *sensors, const evo_q16 *actuators,
			const evo_state *state);

#endif
