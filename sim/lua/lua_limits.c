/* The limits of a run's Lua states (docs/lua.md, "Limits"): the memory a
 * state may hold (an allocator that counts), the task's keys that raise
 * the limits, and the watchdog: a thread beside the count hook that ends
 * the process when a call into a scene script neither returns nor reaches
 * an instruction count (a C library call that runs for seconds), or when
 * SIGINT or SIGTERM came and the call does not stop. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "lua/lua_internal.h"

double evo_lua_now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static double clock_seconds(clockid_t c)
{
	struct timespec ts;
	if (clock_gettime(c, &ts) != 0)
		return 0;
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

double evo_lua_cpu_now(void)
{
	return clock_seconds(CLOCK_THREAD_CPUTIME_ID);
}

/* ---- memory ----------------------------------------------------------- */

/* Lua's allocator contract (lua_Alloc): with ptr NULL, osize is the kind
 * of object, not a size. A refusal is Lua's "not enough memory"; evo_lua
 * turns it into a message that names the script (lua_hooks.c). */
static void *limited_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
	evo_lua_mem *m = ud;
	size_t old = ptr ? osize : 0;
	if (nsize == 0) {
		free(ptr);
		m->used -= old;
		return NULL;
	}
	if (m->enforce && nsize > old && m->used - old + nsize > m->limit) {
		if (!m->hit && m->on_hit)
			m->on_hit(m->ctx);
		m->hit = 1;
		return NULL;
	}
	void *p = realloc(ptr, nsize);
	if (!p)
		return NULL;
	m->used = m->used - old + nsize;
	return p;
}

static int panic(lua_State *L)
{
	fprintf(stderr, "evo: Lua error outside a protected call: %s\n",
		evo_lua_errstr(L, -1));
	abort();
}

lua_State *evo_lua_state_new(size_t memory, evo_lua_mem **mem)
{
	evo_lua_mem *m = calloc(1, sizeof *m);
	if (!m)
		return NULL;
	m->limit = memory;
	lua_State *L = lua_newstate(limited_alloc, m);
	if (!L) {
		free(m);
		return NULL;
	}
	lua_atpanic(L, panic);
	*mem = m;
	return L;
}

void evo_lua_state_close(lua_State *L, evo_lua_mem *mem)
{
	if (L) {
		mem->enforce = 0;
		lua_close(L);
	}
	free(mem);
}

const char *evo_lua_errstr(lua_State *L, int idx)
{
	const char *s = lua_tostring(L, idx);
	if (s)
		return s;
	switch (lua_type(L, idx)) {
	case LUA_TNIL:
		return "(an error value of type nil)";
	case LUA_TBOOLEAN:
		return "(an error value of type boolean)";
	case LUA_TTABLE:
		return "(an error value of type table)";
	case LUA_TFUNCTION:
		return "(an error value of type function)";
	case LUA_TUSERDATA:
	case LUA_TLIGHTUSERDATA:
		return "(an error value of type userdata)";
	case LUA_TTHREAD:
		return "(an error value of type thread)";
	default:
		return "(an error value that is not a string)";
	}
}

/* ---- the task's keys ----------------------------------------------------- */

evo_lua_limits evo_lua_default_limits(void)
{
	return (evo_lua_limits){
	    .budget_scale = 1,
	    .memory = (size_t)EVO_LUA_MEMORY_MB << 20,
	};
}

/* The key table has checked both values at their line (evo_simbatch_parse:
 * LUABUDGET 1..1000, LUAMEMORY 16..65536), so they are read, not checked
 * again; task_path and err stay for callers that may one day check more. */
int evo_lua_limits_read(const evo_simbatch *sb, const char *task_path,
			evo_lua_limits *out, evo_err *err)
{
	(void)task_path;
	(void)err;
	*out = evo_lua_default_limits();
	const char *budget = sb ? evo_simbatch_get(sb, "LUABUDGET") : NULL;
	const char *memory = sb ? evo_simbatch_get(sb, "LUAMEMORY") : NULL;
	if (budget)
		out->budget_scale = (double)strtol(budget, NULL, 10);
	if (memory)
		out->memory = (size_t)strtol(memory, NULL, 10) << 20;
	return 0;
}

/* ---- the watchdog ----------------------------------------------------- */

struct evo_lua_watch {
	struct evo_lua_watch *next;
	pthread_mutex_t mu;
	double deadline; /* 0: no call under way */
	double limit;
	/* the calling thread's CPU clock, and its reading at the call's
	 * start: a call is late when its thread has run past the deadline,
	 * not when a busy machine gave it no time */
	clockid_t cpu;
	double cpu_start;
	char what[64];
	char where[300];
};

static pthread_mutex_t watch_mu = PTHREAD_MUTEX_INITIALIZER;
static struct evo_lua_watch *watch_list;
static volatile sig_atomic_t *stop_flag;
static pthread_once_t watch_once = PTHREAD_ONCE_INIT;

void evo_lua_watch_stop(volatile sig_atomic_t *flag)
{
	pthread_mutex_lock(&watch_mu);
	stop_flag = flag;
	pthread_mutex_unlock(&watch_mu);
}

int evo_lua_stop_signal(void)
{
	volatile sig_atomic_t *f = stop_flag;
	return f ? (int)*f : 0;
}

/* What the watchdog says before it ends the process: plain write(2), as
 * the stuck thread may hold any lock but this one's. */
static void say(const char *msg)
{
	size_t n = strlen(msg);
	while (n > 0) {
		ssize_t w = write(STDERR_FILENO, msg, n);
		if (w <= 0 && errno != EINTR)
			return;
		if (w > 0) {
			msg += w;
			n -= (size_t)w;
		}
	}
}

/* Every 100 ms: a call past its deadline (its limit and the grace), or
 * a stop request that a call has not heeded for half a second, ends the
 * process. Everything a run has written is in files written whole and
 * renamed (base/fileio.h), so nothing finished is lost. */
static void *watchdog(void *arg)
{
	(void)arg;
	double stop_seen = 0;
	for (;;) {
		struct timespec ts = {0, 100000000L};
		nanosleep(&ts, NULL);
		double now = evo_lua_now();
		int sig = evo_lua_stop_signal();
		if (sig && stop_seen == 0)
			stop_seen = now;
		pthread_mutex_lock(&watch_mu);
		for (struct evo_lua_watch *w = watch_list; w; w = w->next) {
			pthread_mutex_lock(&w->mu);
			int late = w->deadline > 0 && now > w->deadline &&
				   clock_seconds(w->cpu) - w->cpu_start >
				       w->limit + EVO_LUA_GRACE;
			int stopped =
			    sig && w->deadline > 0 && now > stop_seen + 0.5;
			if (late || stopped) {
				char msg[600];
				const char *at = w->where[0] ? w->where : "";
				if (stopped)
					snprintf(msg, sizeof msg,
						 "%sstopped by signal %d while "
						 "the script ran %s\n",
						 at, sig, w->what);
				else
					snprintf(
					    msg, sizeof msg,
					    "%sthe script ran past its time "
					    "limit of %g s in %s, in a call "
					    "that did not return (a library "
					    "call such as a string pattern "
					    "that backtracks?); evo stops "
					    "(LUABUDGET raises the limit, "
					    "docs/lua.md)\n",
					    at, w->limit, w->what);
				say(msg);
				_exit(stopped ? 128 + sig : 1);
			}
			pthread_mutex_unlock(&w->mu);
		}
		pthread_mutex_unlock(&watch_mu);
	}
	return NULL;
}

static void start_watchdog(void)
{
	pthread_t t;
	pthread_attr_t a;
	pthread_attr_init(&a);
	pthread_attr_setdetachstate(&a, PTHREAD_CREATE_DETACHED);
	/* the watchdog takes no signal: they go to the threads that run */
	sigset_t all, old;
	sigfillset(&all);
	pthread_sigmask(SIG_SETMASK, &all, &old);
	if (pthread_create(&t, &a, watchdog, NULL) != 0)
		fprintf(stderr, "evo: cannot start the Lua watchdog\n");
	pthread_sigmask(SIG_SETMASK, &old, NULL);
	pthread_attr_destroy(&a);
}

struct evo_lua_watch *evo_lua_watch_add(void)
{
	struct evo_lua_watch *w = calloc(1, sizeof *w);
	if (!w)
		return NULL;
	pthread_mutex_init(&w->mu, NULL);
	pthread_once(&watch_once, start_watchdog);
	pthread_mutex_lock(&watch_mu);
	w->next = watch_list;
	watch_list = w;
	pthread_mutex_unlock(&watch_mu);
	return w;
}

void evo_lua_watch_remove(struct evo_lua_watch *w)
{
	if (!w)
		return;
	pthread_mutex_lock(&watch_mu);
	for (struct evo_lua_watch **p = &watch_list; *p; p = &(*p)->next)
		if (*p == w) {
			*p = w->next;
			break;
		}
	pthread_mutex_unlock(&watch_mu);
	pthread_mutex_destroy(&w->mu);
	free(w);
}

double evo_lua_watch_call(struct evo_lua_watch *w, const char *what,
			  double limit)
{
	double cpu = limit < 0 ? 0 : evo_lua_cpu_now();
	if (!w)
		return cpu;
	pthread_mutex_lock(&w->mu);
	if (limit < 0) {
		w->deadline = 0;
	} else {
		if (pthread_getcpuclockid(pthread_self(), &w->cpu) != 0)
			w->cpu = CLOCK_MONOTONIC;
		w->cpu_start = w->cpu == CLOCK_MONOTONIC ? evo_lua_now() : cpu;
		w->deadline = evo_lua_now() + limit + EVO_LUA_GRACE;
		w->limit = limit;
		snprintf(w->what, sizeof w->what, "%s", what);
		w->where[0] = 0;
	}
	pthread_mutex_unlock(&w->mu);
	return cpu;
}

void evo_lua_watch_where(struct evo_lua_watch *w, const char *where)
{
	if (!w)
		return;
	pthread_mutex_lock(&w->mu);
	snprintf(w->where, sizeof w->where, "%s", where);
	pthread_mutex_unlock(&w->mu);
}

void evo_lua_watch_get_where(struct evo_lua_watch *w, char *out, size_t cap)
{
	if (!w) {
		out[0] = 0;
		return;
	}
	pthread_mutex_lock(&w->mu);
	snprintf(out, cap, "%s", w->where);
	pthread_mutex_unlock(&w->mu);
}
