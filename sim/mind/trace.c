/* Traces (sim/mind/trace.h). */
#include "mind/trace.h"

#include <inttypes.h>

void evo_trace_header(FILE *f, const evo_mindfolder *mind)
{
	const evo_mind *m = &mind->mind;
	fprintf(f, "evo-trace 2\n");
	fprintf(f, "mind %s names %08" PRIx32 "\n", mind->bot_name,
		mind->names_hash);
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

void evo_trace_tick(FILE *f, long tick, const evo_mind *m,
		    const evo_q16 *sensors, const evo_q16 *actuators,
		    const evo_state *state)
{
	fprintf(f, "%ld", tick);
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
