/* Adding a bot, what both worlds repeat (sim/scene/bot.h): the checks of
 * its pose, name and team, and storing it in the scene model's core. */
#include "scene/bot.h"

#include <math.h>

#include "scene/core.h"

evo_bot *evo_core_add_bot(evo_scene_core *c, const evo_bot_def *d,
			  const char *dflt)
{
	if (!isfinite(d->pos[0]) || !isfinite(d->pos[1]) ||
	    !isfinite(d->pos[2]) || !isfinite(d->yaw)) {
		evo_fail(&c->err, "bot: its position or yaw is not a number");
		return NULL;
	}
	if (d->name && d->name[0] && EVO_FIND(c, bot, evo_bot, d->name) >= 0) {
		evo_fail(&c->err, "bot '%s' is defined twice", d->name);
		return NULL;
	}
	if (d->team < -1 || d->team >= EVO_SCENE_MAX_TEAMS) {
		evo_fail(&c->err, "bot: no team %d (at most %d teams)", d->team,
			 EVO_SCENE_MAX_TEAMS);
		return NULL;
	}
	evo_bot *b = evo_store_add((void **)&c->bot, &c->cap_bots, c->n_bots,
				   sizeof *b, &c->err);
	if (!b || evo_store_name(b->name, d->name, dflt, c->n_bots, &c->err))
		return NULL;
	b->def = *d;
	b->def.name = NULL;
	b->body = EVO_BODY_NONE;
	b->team = d->team;
	for (int k = 0; k < 3; k++)
		b->start[k] = d->pos[k];
	b->start_yaw = d->yaw;
	evo_core_note_team(c, d->team);
	return b;
}
