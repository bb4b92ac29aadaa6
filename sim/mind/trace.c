/* Traces (sim/mind/trace.h). */
#include "mind/trace.h"

#include <inttypes.h>

/* The sensors, actuators and skills lines. */
static void names(FILE *f, const evo_mind *m)
{
	fprintf(f, "sensors %u", (unsigned)m->n_sensors);
	for (unsigned i = 0; i < m->n_sensors; i++)
		fprintf(f, " %s", evo_mind_sensor_name(m, i));
	fprintf(f, "\nactuators %u", (unsigned)m->n_actuators);
	for (unsigned i = 0; i < m->n_actuators; i++)
		fprintf(f, " %s", evo_mind_actuator_name(m, i));
	fprintf(f, "\nskills %u", (unsigned)m->n_skills);
	for (unsigned i = 0; i < m->n_skills; i++)
		fprintf(f, " %s", evo_mind_skill_name(m, i));
	fprintf(f, "\n");
}

void evo_trace_header(FILE *f, const evo_mindfolder *mind)
{
	fprintf(f, "evo-trace 2\n");
	fprintf(f, "mind %s names %08" PRIx32 "\n", mind->bot_name,
		mind->names_hash);
	names(f, &mind->mind);
}

void evo_trace_team_header(FILE *f, const char *team,
			   const evo_mindfolder *mind, const char *const *bots,
			   int n_bots)
{
	fprintf(f, "team %s mind %s names %08" PRIx32 " bots %d", team,
		mind->bot_name, mind->names_hash, n_bots);
	for (int i = 0; i < n_bots; i++)
		fprintf(f, " %s", bots[i]);
	fputc('\n', f);
	names(f, &mind->mind);
}

static void values(FILE *f, const evo_mind *m, const evo_q16 *sensors,
		   const evo_q16 *actuators, const evo_state *state)
{
	for (unsigned i = 0; i < m->n_sensors; i++)
		fprintf(f, " %" PRId32, sensors[i]);
	fputs(" |", f);
	for (unsigned i = 0; i < m->n_actuators; i++)
		fprintf(f, " %" PRId32, actuators[i]);
	fputs(" |", f);
	for (unsigned i = 0; i < m->n_skills; i++)
		fprintf(f, " %" PRId32, state->influence[i]);
	fputc('\n', f);
}

void evo_trace_tick_bot(FILE *f, long tick, const char *bot, const evo_mind *m,
			const evo_q16 *sensors, const evo_q16 *actuators,
			const evo_state *state)
{
	fprintf(f, "%ld %s", tick, bot);
	values(f, m, sensors, actuators, state);
}

void evo_trace_tick(FILE *f, long tick, const evo_mind *m,
		    const evo_q16 *sensors, const evo_q16 *actuators,
		    const evo_state *state)
{
	fprintf(f, "%ld", tick);
	values(f, m, sensors, actuators, state);
}
