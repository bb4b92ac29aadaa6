/* One LCM connection with a queue of its own (sim/remote/link.h). */
#define _POSIX_C_SOURCE 200809L
#include "remote/link.h"

#include <errno.h>
#include <lcm/lcm.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>

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
	free(l->url);
	free(l);
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
	if (l->n == 0)
		return 0;
	l->current = l->q[l->head];
	l->head = (l->head + 1) % QUEUE;
	l->n--;
	m->channel = l->current.channel;
	m->data = l->current.data;
	m->len = l->current.len;
	m->recv_utime = l->current.recv_utime;
	return 1;
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
