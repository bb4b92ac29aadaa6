/* A bot's state both worlds keep alike (scene/bot.h): the ring of its
 * last places, which the movement sensor spreads over. */
#include "scene/bot.h"

#include <math.h>

void evo_bot_forget_places(evo_bot *b)
{
	b->hist_n = b->hist_i = 0;
}

void evo_bot_remember_place(evo_bot *b)
{
	b->hist_x[b->hist_i] = b->x;
	b->hist_y[b->hist_i] = b->y;
	b->hist_i = (b->hist_i + 1) % EVO_DOF_HISTORY;
	if (b->hist_n < EVO_DOF_HISTORY)
		b->hist_n++;
}

/* Spread of the last positions: the root of the summed variances of x
 * and y. */
double evo_bot_spread(const evo_bot *b)
{
	int n = b->hist_n < EVO_DOF_HISTORY ? b->hist_n : EVO_DOF_HISTORY;
	if (n < 2)
		return 0;
	/* The positions from the newest back, as two runs of the ring:
	 * hist_i - 1 down to 0, then the end of the ring down. The sums
	 * add in this order, whichever n is. */
	int head = b->hist_i < n ? b->hist_i : n;
	int tail = EVO_DOF_HISTORY - (n - head);
	double mx = 0, my = 0;
	for (int i = b->hist_i - 1; i >= b->hist_i - head; i--) {
		mx += b->hist_x[i];
		my += b->hist_y[i];
	}
	for (int i = EVO_DOF_HISTORY - 1; i >= tail; i--) {
		mx += b->hist_x[i];
		my += b->hist_y[i];
	}
	mx /= n;
	my /= n;
	double v = 0;
	for (int i = b->hist_i - 1; i >= b->hist_i - head; i--) {
		double ex = b->hist_x[i] - mx, ey = b->hist_y[i] - my;
		v += ex * ex + ey * ey;
	}
	for (int i = EVO_DOF_HISTORY - 1; i >= tail; i--) {
		double ex = b->hist_x[i] - mx, ey = b->hist_y[i] - my;
		v += ex * ex + ey * ey;
	}
	return sqrt(v / n);
}
