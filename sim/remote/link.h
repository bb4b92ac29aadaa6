/* evo — one LCM connection (docs/remote.md): raw messages in and out on
 * named channels, received into a queue of evo's own so that a message is
 * only looked at when its reader asks for the next one.
 *
 * Every channel subscribed gets a deep LCM queue, and evo's default URL a
 * receive buffer of RECV_BUF bytes, so that lockstep traffic loses nothing
 * at the rates `make bench` measures. */
#ifndef EVO_LINK_H
#define EVO_LINK_H

#include <stddef.h>
#include <stdint.h>

#include "base/err.h"
#include "remote/wire.h"

/* LCM's own default URL (this machine only: ttl=0). */
#define EVO_LINK_DEFAULT_URL "udpm://239.255.76.67:7667?ttl=0"

typedef struct evo_link evo_link;

/* Connect to url (NULL: EVO_LINK_DEFAULT_URL). NULL with err set. */
evo_link *evo_link_open(const char *url, evo_err *err);
void evo_link_close(evo_link *l);

/* Receive the messages of channel from now on. 0, or -1 with err. */
int evo_link_subscribe(evo_link *l, const char *channel, evo_err *err);

/* A message received: its channel and its bytes (not owned), and when it
 * arrived: LCM's stamp, microseconds of the real-time clock, taken by the
 * kernel as the packet came in where the system allows, so that a message
 * read late still says when it came. */
typedef struct evo_link_msg {
	const char *channel;
	const void *data;
	size_t len;	  /* without the seal */
	int64_t recv_utime;
	int64_t stamp;	  /* the seal's stamp (evo_wire_fresh_take); 0: no key */
} evo_link_msg;

/* The next message, waiting at most timeout_ms for one (0: only what has
 * already come). 1 with *m filled (valid until the next call), 0 when
 * none came in time, -1 with err set when the connection failed. */
int evo_link_next(evo_link *l, int timeout_ms, evo_link_msg *m,
		  evo_err *err);

/* The next message on any of links[0 .. n-1]: one already queued, else
 * the first to come within timeout_ms. 1 with *which its link's index and
 * *m filled (valid until that link's next call), 0 when none came, -1
 * with err set. */
int evo_link_next_any(evo_link *const *links, int n, int timeout_ms,
		      int *which, evo_link_msg *m, evo_err *err);

/* Seal every message published from now on with key k, and take only
 * messages whose seal holds (wire.h): the others are dropped and counted
 * (evo_link_report), the first of each kind said on stderr at once with
 * `who` ("evo", "evo serve") in front. k is copied. */
void evo_link_set_key(evo_link *l, const evo_wire_key *k, const char *who);

/* The messages dropped for their seal so far: forged (no seal, or a MAC
 * that fails the key) and replayed (a stamp too far from this machine's
 * clock). */
void evo_link_drops(const evo_link *l, unsigned long *forged,
		    unsigned long *replayed);

/* One line on stderr with those counts, when there are any. */
void evo_link_report(const evo_link *l);

/* Publish len bytes on channel (sealed when the link has a key). 0, or
 * -1 with err set. */
int evo_link_publish(evo_link *l, const char *channel, const void *data,
		     size_t len, evo_err *err);

/* The URL in use. */
const char *evo_link_url(const evo_link *l);

#endif
