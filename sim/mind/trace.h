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

#endif
