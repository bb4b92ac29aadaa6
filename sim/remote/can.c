/* CAN transports on the host (sim/remote/can.h): SocketCAN, slcan over a
 * serial device or a pseudo-terminal, cannelloni over UDP, candump logs. */
#define _DEFAULT_SOURCE /* cfmakeraw, posix_openpt's friends */
#define _XOPEN_SOURCE 600
#include "remote/can.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

typedef enum kind {
	K_SOCKETCAN,
	K_SLCAN,     /* evo drives an adapter */
	K_SLCAN_PTY, /* evo is the adapter: a peer drives it */
	K_CANNELLONI,
	K_CANDUMP
} kind;

#define QUEUE 256

struct evo_can {
	kind kind;
	int fd;
	char url[256];
	char pty[64];
	char link[256]; /* slcan-pty:?link=PATH: a symbolic link to pty */
	unsigned long unsent; /* frames a full line did not take */
	int line_full;	      /* the last frame was one of them */
	evo_slcan_reader slcan;
	/* frames received and not yet taken */
	evo_can_frame q[QUEUE];
	unsigned head, n;
	/* cannelloni */
	struct sockaddr_storage peer;
	socklen_t peer_len;
	uint8_t seq;
	/* candump: the pace of its time stamps (canplayer's): the first
	 * frame's stamp and when it was read, and a frame read before its
	 * time */
	FILE *log_in, *log_out;
	int paced, started, held, ended;
	double log_t0, wall_t0, held_t;
	evo_can_frame held_f;
	unsigned long log_frames;
	char iface[EVO_CANDUMP_IFACE_MAX];
	unsigned long bad[EVO_CAN_BAD_COUNT];
};

static void push(evo_can *c, const evo_can_frame *f)
{
	if (c->n == QUEUE) { /* the oldest goes: a bus does not wait */
		c->head = (c->head + 1) % QUEUE;
		c->n--;
	}
	c->q[(c->head + c->n) % QUEUE] = *f;
	c->n++;
}

static int pop(evo_can *c, evo_can_frame *f)
{
	if (!c->n)
		return 0;
	*f = c->q[c->head];
	c->head = (c->head + 1) % QUEUE;
	c->n--;
	return 1;
}

static double now_s(void)
{
	struct timeval tv;
	gettimeofday(&tv, NULL);
	return (double)tv.tv_sec + (double)tv.tv_usec * 1e-6;
}

/* A "key=value" of url's query, into out; 1 when there. */
static int query(const char *url, const char *key, char *out, size_t cap)
{
	const char *q = strchr(url, '?');
	size_t kl = strlen(key);
	while (q) {
		q++;
		if (strncmp(q, key, kl) == 0 && q[kl] == '=') {
			size_t n = strcspn(q + kl + 1, "&");
			if (n >= cap)
				n = cap - 1;
			memcpy(out, q + kl + 1, n);
			out[n] = 0;
			return 1;
		}
		q = strchr(q, '&');
	}
	return 0;
}

/* A whole number of a URL (a query's value, a port): digits only, so
 * that "115200x" is no rate and 99999999999999999999 no wrapped one; -1
 * when it is none. */
static long url_number(const char *s)
{
	long v = 0;
	if (!*s || strlen(s) > 9)
		return -1;
	for (; *s; s++) {
		if (*s < '0' || *s > '9')
			return -1;
		v = v * 10 + (*s - '0');
	}
	return v;
}

/* The part of url after "scheme:" and before '?'. */
static void target(const char *url, const char *scheme, char *out,
		   size_t cap)
{
	const char *s = url + strlen(scheme) + 1;
	size_t n = strcspn(s, "?");
	if (n >= cap)
		n = cap - 1;
	memcpy(out, s, n);
	out[n] = 0;
}

/* ---- SocketCAN ------------------------------------------------------------ */

static int open_socketcan(evo_can *c, const char *iface, evo_err *err)
{
	c->fd = socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
	if (c->fd < 0)
		return evo_fail(err,
				"%s: this machine has no SocketCAN: "
				"socket(AF_CAN): %s",
				c->url, strerror(errno));
	struct ifreq ifr;
	memset(&ifr, 0, sizeof ifr);
	if (strlen(iface) >= sizeof ifr.ifr_name)
		return evo_fail(err, "%s: an interface name has at most %zu "
				     "characters",
				c->url, sizeof ifr.ifr_name - 1);
	memcpy(ifr.ifr_name, iface, strlen(iface));
	if (ioctl(c->fd, SIOCGIFINDEX, &ifr) < 0)
		return evo_fail(err, "%s: no CAN interface %s: %s", c->url,
				iface, strerror(errno));
	struct sockaddr_can a;
	memset(&a, 0, sizeof a);
	a.can_family = AF_CAN;
	a.can_ifindex = ifr.ifr_ifindex;
	if (bind(c->fd, (struct sockaddr *)&a, sizeof a) < 0)
		return evo_fail(err, "%s: %s", c->url, strerror(errno));
	return 0;
}

/* ---- slcan ---------------------------------------------------------------- */

/* Write n bytes to a non-blocking serial line, waiting for it to take
 * them at most `wait_s` in all. 0 when written, 1 when the line did not
 * take them all in that time (a peer that does not read, or none at all:
 * a pseudo-terminal nobody opened holds 16 KB, then takes no more; one
 * whose other side closed takes nothing), -1
 * with errno on an error. A line cut by the time limit ends up in the
 * peer's count of malformed lines. */
static int write_all(int fd, const char *s, size_t n, double wait_s)
{
	size_t done = 0;
	double limit = now_s() + wait_s;
	while (done < n) {
		ssize_t w = write(fd, s + done, n - done);
		if (w > 0) {
			done += (size_t)w;
			continue;
		}
		if (w < 0 && errno == EINTR)
			continue;
		/* a pseudo-terminal whose other side has closed answers
		 * EIO, as its reads do: a peer gone takes nothing, and the
		 * link's timeout says it is silent */
		if (w < 0 && errno == EIO)
			return 1;
		if (w < 0 && errno != EAGAIN && errno != EWOULDBLOCK)
			return -1;
		double left = limit - now_s();
		if (left <= 0)
			return 1;
		struct pollfd p = {fd, POLLOUT, 0};
		poll(&p, 1, (int)(left * 1000) + 1);
	}
	return 0;
}

static speed_t baud_of(long b)
{
	switch (b) {
	case 9600: return B9600;
	case 19200: return B19200;
	case 38400: return B38400;
	case 57600: return B57600;
	case 115200: return B115200;
	case 230400: return B230400;
	case 460800: return B460800;
	case 921600: return B921600;
	case 1000000: return B1000000;
	default: return 0;
	}
}

static int raw_tty(int fd, speed_t speed)
{
	struct termios t;
	if (tcgetattr(fd, &t) < 0)
		return -1;
	cfmakeraw(&t);
	if (speed && (cfsetispeed(&t, speed) < 0 || cfsetospeed(&t, speed) < 0))
		return -1;
	return tcsetattr(fd, TCSANOW, &t);
}

/* The Lawicel bit-rate code: S0 10k .. S8 1M. */
static int bitrate_code(long r)
{
	static const long rates[] = {10000,  20000,  50000,  100000, 125000,
				     250000, 500000, 800000, 1000000};
	for (int i = 0; i < 9; i++)
		if (rates[i] == r)
			return i;
	return -1;
}

/* Bytes read from an slcan device: frames queued, answers written. */
static void slcan_bytes(evo_can *c, const char *b, size_t n)
{
	evo_can_frame f[QUEUE];
	char reply[256];
	size_t reply_len = 0;
	int got;
	evo_slcan_read(&c->slcan, b, n, f, QUEUE, &got, c->bad, reply,
		       sizeof reply, &reply_len);
	for (int i = 0; i < got; i++)
		push(c, &f[i]);
	if (reply_len)
		write_all(c->fd, reply, reply_len, 0.1);
}

/* Send an adapter command and wait (up to a second) for its reply: CR is
 * done, BEL refused. */
static int slcan_command(evo_can *c, const char *cmd, evo_err *err)
{
	if (write_all(c->fd, cmd, strlen(cmd), 1.0))
		return evo_fail(err, "%s: cannot write: %s", c->url,
				strerror(errno));
	double limit = now_s() + 1.0;
	while (now_s() < limit) {
		struct pollfd p = {c->fd, POLLIN, 0};
		if (poll(&p, 1, 50) <= 0)
			continue;
		char ch;
		if (read(c->fd, &ch, 1) != 1)
			continue;
		if (ch == '\r')
			return 0;
		if (ch == '\a')
			return evo_fail(err,
					"%s: the adapter refused '%.*s' (BEL)",
					c->url, (int)strcspn(cmd, "\r"), cmd);
		slcan_bytes(c, &ch, 1);
	}
	return evo_fail(err, "%s: the adapter did not answer '%.*s' within a "
			     "second",
			c->url, (int)strcspn(cmd, "\r"), cmd);
}

static int open_slcan(evo_can *c, const char *dev, evo_err *err)
{
	char bv[32] = "500000", dv[32] = "115200";
	query(c->url, "bitrate", bv, sizeof bv);
	query(c->url, "baud", dv, sizeof dv);
	long bitrate = url_number(bv), baud = url_number(dv);
	int code = bitrate_code(bitrate);
	if (code < 0)
		return evo_fail(err,
				"%s: bitrate %s is none of slcan's (10000, "
				"20000, 50000, 100000, 125000, 250000, 500000, "
				"800000, 1000000)",
				c->url, bv);
	if (!baud_of(baud))
		return evo_fail(err, "%s: baud %s is not a serial rate evo "
				     "sets (9600 .. 1000000)",
				c->url, dv);
	c->fd = open(dev, O_RDWR | O_NOCTTY | O_CLOEXEC);
	if (c->fd < 0)
		return evo_fail(err, "%s: cannot open %s: %s", c->url, dev,
				strerror(errno));
	if (raw_tty(c->fd, baud_of(baud)) < 0)
		return evo_fail(err, "%s: %s is not a serial device: %s",
				c->url, dev, strerror(errno));
	/* a line that stops taking bytes drops frames (counted), as a bus
	 * loses them; it never stops evo */
	fcntl(c->fd, F_SETFL, fcntl(c->fd, F_GETFL) | O_NONBLOCK);
	char s[8];
	snprintf(s, sizeof s, "S%d\r", code);
	/* close first: an adapter left open by an earlier program refuses
	 * S; its BEL to this C is no error */
	write_all(c->fd, "C\r", 2, 1.0);
	usleep(20000);
	tcflush(c->fd, TCIFLUSH);
	if (slcan_command(c, s, err) || slcan_command(c, "O\r", err))
		return -1;
	return 0;
}

static int open_slcan_pty(evo_can *c, evo_err *err)
{
	c->fd = posix_openpt(O_RDWR | O_NOCTTY);
	if (c->fd >= 0)
		fcntl(c->fd, F_SETFD, FD_CLOEXEC);
	if (c->fd < 0 || grantpt(c->fd) < 0 || unlockpt(c->fd) < 0)
		return evo_fail(err, "%s: no pseudo-terminal: %s", c->url,
				strerror(errno));
	const char *name = ptsname(c->fd);
	if (!name)
		return evo_fail(err, "%s: no pseudo-terminal name", c->url);
	snprintf(c->pty, sizeof c->pty, "%s", name);
	/* the peer's side raw too, so no line discipline alters a byte */
	int slave = open(c->pty, O_RDWR | O_NOCTTY | O_CLOEXEC);
	if (slave >= 0) {
		raw_tty(slave, 0);
		close(slave);
	}
	fcntl(c->fd, F_SETFL, fcntl(c->fd, F_GETFL) | O_NONBLOCK);
	char link[sizeof c->link];
	if (!query(c->url, "link", link, sizeof link))
		return 0;
	if (!link[0])
		return evo_fail(err, "%s: link= names no path", c->url);
	/* a link left by a server that was killed is replaced; anything
	 * else at that path is not evo's to remove */
	struct stat st;
	if (lstat(link, &st) == 0 && !S_ISLNK(st.st_mode))
		return evo_fail(err,
				"%s: %s exists and is no symbolic link: evo "
				"does not replace it",
				c->url, link);
	unlink(link);
	if (symlink(c->pty, link) != 0)
		return evo_fail(err, "%s: cannot link %s to %s: %s", c->url,
				link, c->pty, strerror(errno));
	snprintf(c->link, sizeof c->link, "%s", link);
	return 0;
}

/* ---- cannelloni over UDP ------------------------------------------------ */

static int open_cannelloni(evo_can *c, const char *hostport, evo_err *err)
{
	char host[200];
	const char *colon = strrchr(hostport, ':');
	if (!colon || colon == hostport || !colon[1])
		return evo_fail(err,
				"%s: expected cannelloni:HOST:PORT[?local=PORT]",
				c->url);
	snprintf(host, sizeof host, "%.*s", (int)(colon - hostport), hostport);
	struct addrinfo hints, *ai = NULL;
	memset(&hints, 0, sizeof hints);
	hints.ai_family = AF_INET;
	hints.ai_socktype = SOCK_DGRAM;
	int rc = getaddrinfo(host, colon + 1, &hints, &ai);
	if (rc || !ai)
		return evo_fail(err, "%s: %s: %s", c->url, host,
				gai_strerror(rc));
	memcpy(&c->peer, ai->ai_addr, ai->ai_addrlen);
	c->peer_len = ai->ai_addrlen;
	freeaddrinfo(ai);
	char lp[16];
	if (!query(c->url, "local", lp, sizeof lp))
		snprintf(lp, sizeof lp, "%.15s", colon + 1);
	long local = url_number(lp);
	if (local < 1 || local > 65535)
		return evo_fail(err, "%s: local port %s is not a port", c->url,
				lp);
	/* Not inherited: a program evo starts must not hold the port (nor
	 * the device, the pseudo-terminal or the log) after evo closes it. */
	c->fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
	if (c->fd < 0)
		return evo_fail(err, "%s: %s", c->url, strerror(errno));
	struct sockaddr_in a;
	memset(&a, 0, sizeof a);
	a.sin_family = AF_INET;
	a.sin_port = htons((uint16_t)local);
	a.sin_addr.s_addr = htonl(INADDR_ANY);
	if (bind(c->fd, (struct sockaddr *)&a, sizeof a) < 0)
		return evo_fail(err, "%s: cannot listen on UDP port %ld: %s",
				c->url, local, strerror(errno));
	return 0;
}

/* ---- opening -------------------------------------------------------------- */

static const char *const schemes[] = {"socketcan:", "slcan-pty:", "slcan:",
				     "cannelloni:", "candump:", NULL};

static int unknown_url(const char *url, evo_err *err)
{
	return evo_fail(err,
			"'%s' is no CAN URL evo knows: socketcan:IFACE, "
			"slcan:DEVICE, slcan-pty:, cannelloni:HOST:PORT "
			"or candump:FILE (docs/can.md)",
			url);
}

int evo_can_url_check(const char *url, evo_err *err)
{
	for (int i = 0; schemes[i]; i++)
		if (strncmp(url, schemes[i], strlen(schemes[i])) == 0)
			return 0;
	return unknown_url(url, err);
}

evo_can *evo_can_open(const char *url, evo_err *err)
{
	evo_can *c = calloc(1, sizeof *c);
	if (!c) {
		evo_fail(err, "out of memory");
		return NULL;
	}
	c->fd = -1;
	snprintf(c->url, sizeof c->url, "%s", url);
	char t[256];
	int rc;
	if (strncmp(url, "socketcan:", 10) == 0) {
		c->kind = K_SOCKETCAN;
		target(url, "socketcan", t, sizeof t);
		rc = open_socketcan(c, t, err);
	} else if (strncmp(url, "slcan-pty:", 10) == 0) {
		c->kind = K_SLCAN_PTY;
		c->slcan.as_adapter = 1;
		rc = open_slcan_pty(c, err);
	} else if (strncmp(url, "slcan:", 6) == 0) {
		c->kind = K_SLCAN;
		target(url, "slcan", t, sizeof t);
		rc = open_slcan(c, t, err);
	} else if (strncmp(url, "cannelloni:", 11) == 0) {
		c->kind = K_CANNELLONI;
		target(url, "cannelloni", t, sizeof t);
		rc = open_cannelloni(c, t, err);
	} else if (strncmp(url, "candump:", 8) == 0) {
		c->kind = K_CANDUMP;
		target(url, "candump", t, sizeof t);
		c->log_in = fopen(t, "re");
		rc = c->log_in ? 0
			       : evo_fail(err, "%s: cannot read %s: %s", url, t,
					  strerror(errno));
		/* ?pace=0: as fast as it is read (canplayer -t) */
		char v[8];
		c->paced = !(query(url, "pace", v, sizeof v) &&
			     strcmp(v, "0") == 0);
		snprintf(c->iface, sizeof c->iface, "evo");
		if (rc == 0) {
			char out[300];
			snprintf(out, sizeof out, "%s.sent", t);
			/* O_NOFOLLOW: FILE.sent may come with FILE, from
			 * someone else; a link there would have evo append
			 * frames to whatever file it names */
			int fd = open(out,
				      O_WRONLY | O_APPEND | O_CREAT |
					  O_NOFOLLOW | O_CLOEXEC,
				      0644);
			int e = errno;
			c->log_out = fd >= 0 ? fdopen(fd, "a") : NULL;
			if (!c->log_out) {
				if (fd >= 0) {
					e = errno;
					close(fd);
				}
				rc = evo_fail(err, "%s: cannot write %s: %s",
					      url, out,
					      e == ELOOP
						  ? "a symbolic link, which "
						    "evo does not write "
						    "through"
						  : strerror(e));
			}
		}
	} else {
		rc = unknown_url(url, err);
	}
	if (rc) {
		evo_can_close(c);
		return NULL;
	}
	return c;
}

void evo_can_close(evo_can *c)
{
	if (!c)
		return;
	if (c->kind == K_SLCAN && c->fd >= 0)
		write_all(c->fd, "C\r", 2, 0.1);
	if (c->link[0]) {
		/* the link goes with the pty, unless another has taken it */
		char to[sizeof c->pty];
		ssize_t n = readlink(c->link, to, sizeof to - 1);
		if (n > 0 && (size_t)n == strlen(c->pty) &&
		    memcmp(to, c->pty, (size_t)n) == 0)
			unlink(c->link);
	}
	if (c->fd >= 0)
		close(c->fd);
	if (c->log_in)
		fclose(c->log_in);
	if (c->log_out)
		fclose(c->log_out);
	free(c);
}

/* ---- frames ---------------------------------------------------------------- */

int evo_can_send(evo_can *c, const evo_can_frame *f, evo_err *err)
{
	if (f->id > 0x7FF || f->len > 8)
		return evo_fail(err, "%s: frame id %#x, %u bytes: not a classic "
				     "CAN frame with an 11-bit id",
				c->url, (unsigned)f->id, (unsigned)f->len);
	switch (c->kind) {
	case K_SOCKETCAN: {
		struct can_frame cf;
		memset(&cf, 0, sizeof cf);
		cf.can_id = f->id;
		cf.can_dlc = f->len;
		memcpy(cf.data, f->data, f->len);
		if (write(c->fd, &cf, sizeof cf) != (ssize_t)sizeof cf)
			return evo_fail(err, "%s: cannot send: %s", c->url,
					strerror(errno));
		return 0;
	}
	case K_SLCAN:
	case K_SLCAN_PTY: {
		char line[EVO_SLCAN_LINE_MAX + 1];
		size_t n = evo_slcan_encode(f, line);
		/* a line that took the last frame gets 2 ms to take this
		 * one; a line still full, none */
		int rc = write_all(c->fd, line, n, c->line_full ? 0 : 0.002);
		if (rc < 0)
			return evo_fail(err, "%s: cannot send: %s", c->url,
					strerror(errno));
		c->unsent += (unsigned long)rc;
		c->line_full = rc == 1;
		return 0;
	}
	case K_CANNELLONI: {
		uint8_t d[64];
		size_t n = evo_cannelloni_encode(f, 1, c->seq++, d, sizeof d);
		if (sendto(c->fd, d, n, 0, (struct sockaddr *)&c->peer,
			   c->peer_len) != (ssize_t)n)
			return evo_fail(err, "%s: cannot send: %s", c->url,
					strerror(errno));
		return 0;
	}
	case K_CANDUMP: {
		char line[EVO_CANDUMP_LINE_MAX];
		size_t n = evo_candump_format(f, now_s(), c->iface, line);
		if (fwrite(line, 1, n, c->log_out) != n || fflush(c->log_out))
			return evo_fail(err, "%s: cannot write: %s", c->url,
					strerror(errno));
		return 0;
	}
	}
	return evo_fail(err, "%s: cannot send", c->url);
}

/* Read what fd has into the queue. 0, or -1 with err set. */
static int take(evo_can *c, evo_err *err)
{
	switch (c->kind) {
	case K_SOCKETCAN: {
		struct can_frame cf;
		ssize_t r = read(c->fd, &cf, sizeof cf);
		if (r < 0)
			return errno == EINTR ? 0
					      : evo_fail(err, "%s: %s", c->url,
							 strerror(errno));
		if (r != (ssize_t)sizeof cf || cf.can_dlc > 8) {
			c->bad[EVO_CAN_BAD_LENGTH]++;
			return 0;
		}
		if (cf.can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_ERR_FLAG)) {
			c->bad[EVO_CAN_BAD_NOT_OURS]++;
			return 0;
		}
		evo_can_frame f = {(uint16_t)cf.can_id, cf.can_dlc, {0}};
		memcpy(f.data, cf.data, cf.can_dlc);
		push(c, &f);
		return 0;
	}
	case K_SLCAN:
	case K_SLCAN_PTY: {
		char b[512];
		ssize_t r = read(c->fd, b, sizeof b);
		if (r < 0 && (errno == EINTR || errno == EAGAIN || errno == EIO))
			return 0; /* a pty with no peer yet reads EIO */
		if (r < 0)
			return evo_fail(err, "%s: %s", c->url, strerror(errno));
		slcan_bytes(c, b, (size_t)r);
		return 0;
	}
	case K_CANNELLONI: {
		uint8_t d[2048];
		struct sockaddr_storage from;
		socklen_t from_len = sizeof from;
		ssize_t r = recvfrom(c->fd, d, sizeof d, 0,
				     (struct sockaddr *)&from, &from_len);
		if (r < 0)
			return errno == EINTR ? 0
					      : evo_fail(err, "%s: %s", c->url,
							 strerror(errno));
		/* Only the peer the URL names, address and port, as the
		 * reference cannelloni takes only its remote's: anyone
		 * else who can reach the port is not on this bus. */
		const struct sockaddr_in *a = (const struct sockaddr_in *)&from,
					 *p = (const struct sockaddr_in *)&c->peer;
		if (from.ss_family != AF_INET ||
		    a->sin_addr.s_addr != p->sin_addr.s_addr ||
		    a->sin_port != p->sin_port) {
			c->bad[EVO_CAN_BAD_SOURCE]++;
			return 0;
		}
		evo_can_frame f[QUEUE];
		int n;
		evo_cannelloni_decode(d, (size_t)r, f, QUEUE, &n, c->bad);
		for (int i = 0; i < n; i++)
			push(c, &f[i]);
		return 0;
	}
	case K_CANDUMP:
		break;
	}
	return 0;
}

/* The next frame of a candump log, with its time stamp; 0 at its end. */
static int candump_next(evo_can *c, evo_can_frame *f, double *t)
{
	char line[EVO_CANDUMP_LINE_MAX + 2];
	while (fgets(line, sizeof line, c->log_in)) {
		size_t n = strcspn(line, "\r\n");
		if (n == strlen(line) && !feof(c->log_in)) {
			/* longer than any log line: skip the rest */
			c->bad[EVO_CAN_BAD_OVERLONG]++;
			int ch;
			while ((ch = fgetc(c->log_in)) != EOF && ch != '\n')
				;
			continue;
		}
		if (n == 0)
			continue;
		char iface[EVO_CANDUMP_IFACE_MAX];
		evo_can_bad why;
		if (evo_candump_parse(line, n, t, iface, f, &why))
			return 1;
		c->bad[why]++;
	}
	return 0;
}

/* A log read as the bus it recorded: each frame when its time stamp says,
 * counted from the first (as canplayer plays a log; a stamp earlier than
 * the one before is due at once), waiting at most timeout_ms for it. At
 * the end of the log: -1, saying so, never a wait for more. */
static int candump_recv(evo_can *c, int timeout_ms, evo_can_frame *f,
			evo_err *err)
{
	if (!c->held) {
		if (!candump_next(c, &c->held_f, &c->held_t)) {
			c->ended = 1;
			return evo_fail(err,
					"%s: the log ends after %lu frame%s",
					c->url, c->log_frames,
					c->log_frames == 1 ? "" : "s");
		}
		c->held = 1;
		if (!c->started) {
			c->started = 1;
			c->log_t0 = c->held_t;
			c->wall_t0 = now_s();
		}
	}
	if (c->paced) {
		double due = c->wall_t0 + (c->held_t - c->log_t0);
		double wait = due - now_s();
		if (wait > timeout_ms / 1000.0) {
			struct timespec ts = {timeout_ms / 1000,
					      (long)(timeout_ms % 1000) * 1000000};
			nanosleep(&ts, NULL);
			return 0;
		}
		if (wait > 0) {
			struct timespec ts = {(time_t)wait,
					      (long)((wait - (double)(time_t)wait) *
						     1e9)};
			nanosleep(&ts, NULL);
		}
	}
	*f = c->held_f;
	c->held = 0;
	c->log_frames++;
	return 1;
}

int evo_can_ended(const evo_can *c)
{
	return c->ended;
}

int evo_can_recv(evo_can *c, int timeout_ms, evo_can_frame *f, evo_err *err)
{
	if (pop(c, f))
		return 1;
	if (c->kind == K_CANDUMP)
		return candump_recv(c, timeout_ms, f, err);
	double limit = now_s() + timeout_ms / 1000.0;
	for (;;) {
		struct pollfd p = {c->fd, POLLIN, 0};
		int wait = (int)((limit - now_s()) * 1000);
		int r = poll(&p, 1, wait > 0 ? wait : 0);
		if (r < 0 && errno != EINTR)
			return evo_fail(err, "%s: %s", c->url, strerror(errno));
		if (r > 0) {
			if (p.revents & (POLLIN | POLLERR | POLLHUP)) {
				if (take(c, err))
					return -1;
			}
			if (pop(c, f))
				return 1;
			if (p.revents & POLLHUP) {
				/* a pty whose peer closed: no busy loop */
				struct timespec ms = {0, 5000000};
				nanosleep(&ms, NULL);
			}
		}
		if (now_s() >= limit)
			return 0;
	}
}

const unsigned long *evo_can_dropped(const evo_can *c)
{
	return c->bad;
}

const char *evo_can_pty_name(const evo_can *c)
{
	return c->kind == K_SLCAN_PTY ? c->pty : NULL;
}

const char *evo_can_pty_link(const evo_can *c)
{
	return c->link[0] ? c->link : NULL;
}

unsigned long evo_can_unsent(const evo_can *c)
{
	return c->unsent;
}
