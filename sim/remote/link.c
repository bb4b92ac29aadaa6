/* One LCM connection with a queue of its own (sim/remote/link.h). */
#define _POSIX_C_SOURCE 200809L
#include "remote/link.h"

#include <errno.h>
#include <lcm/lcm.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define QUEUE 1024	   /* messages received and not yet read */
#define LCM_QUEUE 10000	   /* LCM's own queue per channel */
#define MAX_CHANNELS 16

typedef struct queued {
	char *channel;
	void *data;
	size_t len;
	int64_t recv_utime;
} queued;

struct evo_link {
	lcm_t *lcm;
	char *url;
	queued q[QUEUE];
	unsigned head, n;
	queued current; /* the last message given out, freed on the next */
	int overflow;	/* messages dropped because the queue was full */
	lcm_subscription_t *sub[MAX_CHANNELS];
	unsigned n_sub;
	evo_wire_key key; /* len 0: none */
	const char *who;
	int64_t last_stamp;
	unsigned long forged, replayed;
	unsigned char out[EVO_WIRE_MAX_BYTES + EVO_WIRE_SEAL_BYTES];
};

static void on_message(const lcm_recv_buf_t *rb, const char *channel,
		       void *user)
{
	evo_link *l = user;
	if (l->n == QUEUE) {
		l->overflow++;
		return;
	}
	queued m = {strdup(channel), malloc(rb->data_size ? rb->data_size : 1),
		    rb->data_size, rb->recv_utime};
	if (!m.channel || !m.data) {
		free(m.channel);
		free(m.data);
		l->overflow++;
		return;
	}
	memcpy(m.data, rb->data, rb->data_size);
	l->q[(l->head + l->n) % QUEUE] = m;
	l->n++;
}

evo_link *evo_link_open(const char *url, evo_err *err)
{
	if (!url)
		url = EVO_LINK_DEFAULT_URL;
	evo_link *l = calloc(1, sizeof *l);
	if (!l || !(l->url = strdup(url))) {
		free(l);
		evo_fail(err, "out of memory");
		return NULL;
	}
	l->lcm = lcm_create(url);
	if (!l->lcm) {
		evo_fail(err,
			 "cannot open LCM at '%s' (a URL such as %s; is "
			 "there a route for multicast?)",
			 url, EVO_LINK_DEFAULT_URL);
		free(l->url);
		free(l);
		return NULL;
	}
	return l;
}

static void drop(queued *m)
{
	free(m->channel);
	free(m->data);
	memset(m, 0, sizeof *m);
}

void evo_link_close(evo_link *l)
{
	if (!l)
		return;
	for (unsigned i = 0; i < l->n_sub; i++)
		lcm_unsubscribe(l->lcm, l->sub[i]);
	lcm_destroy(l->lcm);
	while (l->n) {
		drop(&l->q[l->head]);
		l->head = (l->head + 1) % QUEUE;
		l->n--;
	}
	drop(&l->current);
	memset(&l->key, 0, sizeof l->key);
	free(l->url);
	free(l);
}

void evo_link_set_key(evo_link *l, const evo_wire_key *k, const char *who)
{
	l->key = *k;
	l->who = who;
}

void evo_link_drops(const evo_link *l, unsigned long *forged,
		    unsigned long *replayed)
{
	*forged = l->forged;
	*replayed = l->replayed;
}

void evo_link_report(const evo_link *l)
{
	if (l->forged || l->replayed)
		fprintf(stderr,
			"%s: LCM at %s: dropped %lu forged and %lu replayed "
			"message%s (they failed the key)\n",
			l->who, l->url, l->forged, l->replayed,
			l->forged + l->replayed == 1 ? "" : "s");
}

static int64_t real_us(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_REALTIME, &ts);
	return (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

/* With a key: 1 when the current message's seal holds (its length and
 * stamp then without the seal), 0 when it was dropped. */
static int unseal(evo_link *l, size_t *len, int64_t *stamp)
{
	char why[256];
	evo_wire_reason rc = evo_wire_unseal(
	    &l->key, l->current.channel, l->current.data, l->current.len,
	    real_us(), len, stamp, why, sizeof why);
	if (rc == EVO_WIRE_OK)
		return 1;
	unsigned long *count = rc == EVO_WIRE_FORGED ? &l->forged : &l->replayed;
	if ((*count)++ == 0)
		fprintf(stderr,
			"%s: LCM at %s: dropped %s (%s); later ones are "
			"counted and reported at the end\n",
			l->who, l->url, why, evo_wire_reason_name(rc));
	return 0;
}

int evo_link_subscribe(evo_link *l, const char *channel, evo_err *err)
{
	if (l->n_sub == MAX_CHANNELS)
		return evo_fail(err, "LCM: more than %d channels", MAX_CHANNELS);
	lcm_subscription_t *s = lcm_subscribe(l->lcm, channel, on_message, l);
	if (!s)
		return evo_fail(err, "LCM: cannot subscribe to %s", channel);
	lcm_subscription_set_queue_capacity(s, LCM_QUEUE);
	l->sub[l->n_sub++] = s;
	return 0;
}

int evo_link_next(evo_link *l, int timeout_ms, evo_link_msg *m, evo_err *err)
{
	drop(&l->current);
	if (l->n == 0) {
		int r = lcm_handle_timeout(l->lcm, timeout_ms);
		if (r < 0 && errno != EINTR)
			return evo_fail(err, "LCM at %s: receiving failed",
					l->url);
	}
	/* messages that fail the key are dropped here, before anyone
	 * decodes them */
	while (l->n) {
		drop(&l->current);
		l->current = l->q[l->head];
		l->head = (l->head + 1) % QUEUE;
		l->n--;
		size_t len = l->current.len;
		int64_t stamp = 0;
		if (l->key.len && !unseal(l, &len, &stamp))
			continue;
		m->channel = l->current.channel;
		m->data = l->current.data;
		m->len = len;
		m->recv_utime = l->current.recv_utime;
		m->stamp = stamp;
		return 1;
	}
	return 0;
}

#define MAX_ANY 64

int evo_link_next_any(evo_link *const *links, int n, int timeout_ms,
		      int *which, evo_link_msg *m, evo_err *err)
{
	if (n < 1 || n > MAX_ANY)
		return evo_fail(err, "LCM: %d connections to wait on", n);
	for (int i = 0; i < n; i++)
		if (links[i]->n) {
			*which = i;
			return evo_link_next(links[i], 0, m, err);
		}
	struct pollfd fd[MAX_ANY];
	for (int i = 0; i < n; i++)
		fd[i] = (struct pollfd){lcm_get_fileno(links[i]->lcm), POLLIN, 0};
	int r = poll(fd, (nfds_t)n, timeout_ms);
	if (r < 0 && errno != EINTR)
		return evo_fail(err, "LCM: waiting failed: %s", strerror(errno));
	for (int i = 0; r > 0 && i < n; i++) {
		if (!fd[i].revents)
			continue;
		/* readable: lcm_handle returns at once, without the select
		 * lcm_handle_timeout would make first */
		drop(&links[i]->current);
		if (lcm_handle(links[i]->lcm) != 0)
			return evo_fail(err, "LCM at %s: receiving failed",
					links[i]->url);
		int got = evo_link_next(links[i], 0, m, err);
		if (got != 0) {
			*which = i;
			return got;
		}
	}
	return 0;
}

int evo_link_publish(evo_link *l, const char *channel, const void *data,
		     size_t len, evo_err *err)
{
	if (l->key.len) {
		/* sealed afresh on every send: a message sent again gets a
		 * new stamp, so its receiver does not take it for a replay */
		if (len > EVO_WIRE_MAX_BYTES)
			return evo_fail(err, "LCM at %s: a message of %zu bytes",
					l->url, len);
		memcpy(l->out, data, len);
		int n = evo_wire_seal(&l->key, channel, l->out, len,
				      sizeof l->out,
				      evo_wire_stamp(&l->last_stamp));
		if (n < 0)
			return evo_fail(err, "LCM at %s: cannot seal a message",
					l->url);
		data = l->out;
		len = (size_t)n;
	}
	if (len > 0x7fffffff ||
	    lcm_publish(l->lcm, channel, data, (unsigned)len) != 0)
		return evo_fail(err, "LCM at %s: cannot publish on %s", l->url,
				channel);
	return 0;
}

const char *evo_link_url(const evo_link *l)
{
	return l->url;
}
