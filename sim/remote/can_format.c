/* CAN frames in cannelloni datagrams and candump log lines
 * (sim/remote/can.h): pure functions, fuzzed. */
#include "remote/can.h"

#include <stdio.h>
#include <string.h>

const char *evo_can_bad_name(evo_can_bad b)
{
	static const char *const names[EVO_CAN_BAD_COUNT] = {
	    "syntax", "length", "overlong", "not evo's", "version", "reply",
	    "not from the peer"};
	return (unsigned)b < EVO_CAN_BAD_COUNT ? names[b] : "?";
}

/* ---- cannelloni ---------------------------------------------------------- */

#define CAN_EFF 0x80000000u /* <linux/can.h>'s flags, as on the wire */
#define CAN_RTR 0x40000000u
#define CAN_ERR 0x20000000u
#define CANFD 0x80u	    /* in the length byte */

int evo_cannelloni_decode(const uint8_t *d, size_t len, evo_can_frame *out,
			  int max, int *n, unsigned long *bad)
{
	*n = 0;
	if (len < 5) {
		bad[EVO_CAN_BAD_SYNTAX]++;
		return -1;
	}
	if (d[0] != EVO_CANNELLONI_VERSION || d[1] != 0) {
		bad[EVO_CAN_BAD_VERSION]++;
		return -1;
	}
	unsigned count = (unsigned)d[3] << 8 | d[4];
	size_t pos = 5;
	for (unsigned k = 0; k < count; k++) {
		if (len - pos < 5) {
			bad[EVO_CAN_BAD_LENGTH]++;
			return -1;
		}
		uint32_t id = (uint32_t)d[pos] << 24 | (uint32_t)d[pos + 1] << 16 |
			      (uint32_t)d[pos + 2] << 8 | d[pos + 3];
		unsigned l = d[pos + 4];
		pos += 5;
		int fd = (l & CANFD) != 0;
		if (fd) {
			/* a flags byte, then up to 64 bytes */
			l &= ~CANFD;
			if (len - pos < 1) {
				bad[EVO_CAN_BAD_LENGTH]++;
				return -1;
			}
			pos++;
		}
		if (l > (fd ? 64u : 8u) || len - pos < l) {
			bad[EVO_CAN_BAD_LENGTH]++;
			return -1;
		}
		if (fd || (id & (CAN_EFF | CAN_RTR | CAN_ERR)) || id > 0x7FF) {
			bad[EVO_CAN_BAD_NOT_OURS]++;
		} else if (*n < max) {
			evo_can_frame *f = &out[(*n)++];
			f->id = (uint16_t)id;
			f->len = (uint8_t)l;
			memcpy(f->data, d + pos, l);
		}
		pos += l;
	}
	if (pos != len) {
		bad[EVO_CAN_BAD_LENGTH]++;
		return -1;
	}
	return 0;
}

size_t evo_cannelloni_encode(const evo_can_frame *f, int n, uint8_t seq,
			     uint8_t *out, size_t cap)
{
	if (n < 0 || n > 0xFFFF || cap < 5)
		return 0;
	out[0] = EVO_CANNELLONI_VERSION;
	out[1] = 0; /* DATA */
	out[2] = seq;
	out[3] = (uint8_t)(n >> 8);
	out[4] = (uint8_t)n;
	size_t pos = 5;
	for (int k = 0; k < n; k++) {
		unsigned l = f[k].len > 8 ? 8 : f[k].len;
		if (cap - pos < 5 + l)
			return 0;
		uint32_t id = f[k].id & 0x7FFu;
		out[pos] = (uint8_t)(id >> 24);
		out[pos + 1] = (uint8_t)(id >> 16);
		out[pos + 2] = (uint8_t)(id >> 8);
		out[pos + 3] = (uint8_t)id;
		out[pos + 4] = (uint8_t)l;
		memcpy(out + pos + 5, f[k].data, l);
		pos += 5 + l;
	}
	return pos;
}

/* ---- candump logs ----------------------------------------------------- */

static int hexval(char c)
{
	return c >= '0' && c <= '9'   ? c - '0'
	       : c >= 'a' && c <= 'f' ? c - 'a' + 10
	       : c >= 'A' && c <= 'F' ? c - 'A' + 10
				      : -1;
}

static int refuse(evo_can_bad *why, evo_can_bad b)
{
	*why = b;
	return 0;
}

int evo_candump_parse(const char *line, size_t len, double *t, char *iface,
		      evo_can_frame *f, evo_can_bad *why)
{
	if (len > EVO_CANDUMP_LINE_MAX)
		return refuse(why, EVO_CAN_BAD_OVERLONG);
	/* (SECONDS.MICROS) */
	size_t i = 0;
	if (len < 1 || line[i++] != '(')
		return refuse(why, EVO_CAN_BAD_SYNTAX);
	double sec = 0, frac = 0, scale = 1;
	int digits = 0, dot = 0;
	for (; i < len && line[i] != ')'; i++) {
		char c = line[i];
		if (c == '.' && !dot) {
			dot = 1;
		} else if (c >= '0' && c <= '9' && digits < 20) {
			digits++;
			if (dot) {
				scale /= 10;
				frac += (c - '0') * scale;
			} else {
				sec = sec * 10 + (c - '0');
			}
		} else {
			return refuse(why, EVO_CAN_BAD_SYNTAX);
		}
	}
	if (i >= len || !digits || !dot)
		return refuse(why, EVO_CAN_BAD_SYNTAX);
	i++; /* ')' */
	if (i >= len || line[i++] != ' ')
		return refuse(why, EVO_CAN_BAD_SYNTAX);
	/* IFACE */
	size_t k = 0;
	for (; i < len && line[i] != ' '; i++) {
		char c = line[i];
		/* an interface name: printable, no space (Linux allows more,
		 * but no CAN interface is named otherwise) */
		if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
		      (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.'))
			return refuse(why, EVO_CAN_BAD_SYNTAX);
		if (k + 1 >= EVO_CANDUMP_IFACE_MAX)
			return refuse(why, EVO_CAN_BAD_OVERLONG);
		iface[k++] = c;
	}
	iface[k] = 0;
	if (!k || i >= len)
		return refuse(why, EVO_CAN_BAD_SYNTAX);
	i++;
	/* ID#... */
	size_t id_start = i;
	uint32_t id = 0;
	for (; i < len && line[i] != '#'; i++) {
		int v = hexval(line[i]);
		if (v < 0 || i - id_start >= 8)
			return refuse(why, EVO_CAN_BAD_SYNTAX);
		id = id << 4 | (uint32_t)v;
	}
	size_t id_digits = i - id_start;
	if (i >= len || (id_digits != 3 && id_digits != 8))
		return refuse(why, EVO_CAN_BAD_SYNTAX);
	i++; /* '#' */
	if (id_digits == 8 || (i < len && (line[i] == 'R' || line[i] == 'r' ||
					   line[i] == '#')))
		return refuse(why, EVO_CAN_BAD_NOT_OURS);
	if (id > 0x7FF)
		return refuse(why, EVO_CAN_BAD_SYNTAX);
	/* python-can's direction flag: " R" received, " T" sent by the
	 * logging node; either way a frame that was on the bus */
	if (len - i >= 2 && line[len - 2] == ' ' &&
	    (line[len - 1] == 'R' || line[len - 1] == 'T'))
		len -= 2;
	size_t data = len - i;
	if (data % 2)
		return refuse(why, EVO_CAN_BAD_SYNTAX);
	if (data / 2 > 8)
		return refuse(why, EVO_CAN_BAD_LENGTH);
	for (size_t b = 0; b < data / 2; b++) {
		int hi = hexval(line[i + 2 * b]), lo = hexval(line[i + 2 * b + 1]);
		if (hi < 0 || lo < 0)
			return refuse(why, EVO_CAN_BAD_SYNTAX);
		f->data[b] = (uint8_t)(hi << 4 | lo);
	}
	f->id = (uint16_t)id;
	f->len = (uint8_t)(data / 2);
	*t = sec + frac;
	return 1;
}

size_t evo_candump_format(const evo_can_frame *f, double t, const char *iface,
			  char *out)
{
	static const char hex[] = "0123456789ABCDEF";
	long long sec = (long long)t;
	long usec = (long)((t - (double)sec) * 1e6 + 0.5);
	if (usec >= 1000000) {
		sec++;
		usec -= 1000000;
	}
	int n = snprintf(out, EVO_CANDUMP_LINE_MAX, "(%lld.%06ld) %.*s %03X#",
			 sec, usec, EVO_CANDUMP_IFACE_MAX - 1, iface,
			 (unsigned)(f->id & 0x7FF));
	if (n < 0 || n >= EVO_CANDUMP_LINE_MAX - 18)
		return 0;
	size_t k = (size_t)n;
	for (unsigned b = 0; b < f->len && b < 8; b++) {
		out[k++] = hex[f->data[b] >> 4];
		out[k++] = hex[f->data[b] & 15];
	}
	out[k++] = '\n';
	out[k] = 0;
	return k;
}

/* ---- slcan as the host reads it ---------------------------------------- */

static void answer(const char *a, char *reply, size_t cap, size_t *len)
{
	size_t n = strlen(a);
	if (cap - *len >= n) {
		memcpy(reply + *len, a, n);
		*len += n;
	}
}

/* Why core refused a 't' line, as the host counts it. Core takes at most
 * the longest line of 8 bytes; a longer one of hex digits only (a DLC of
 * 9 and 9 bytes, say) is a length past 8, as docs/can.md says, not a
 * syntax error. */
static evo_can_bad slcan_bad(const char *s, size_t n, evo_wire_bad wb)
{
	if (wb == EVO_WIRE_BAD_LENGTH)
		return EVO_CAN_BAD_LENGTH;
	if (wb != EVO_WIRE_BAD_OVERLONG)
		return EVO_CAN_BAD_SYNTAX;
	for (size_t i = 1; i < n; i++)
		if (hexval(s[i]) < 0)
			return EVO_CAN_BAD_SYNTAX;
	return EVO_CAN_BAD_LENGTH;
}

/* One complete line (without its end). */
static void slcan_line(evo_slcan_reader *r, const char *s, size_t n,
		       evo_can_frame *out, int max, int *got,
		       unsigned long *bad, char *reply, size_t cap,
		       size_t *reply_len)
{
	if (n == 0)
		return;
	switch (s[0]) {
	case 't': {
		evo_can_frame f;
		evo_wire_bad wb;
		evo_slcan_result res = evo_slcan_decode(s, n, &f, &wb);
		if (res == EVO_SLCAN_FRAME) {
			if (*got < max)
				out[(*got)++] = f;
			else
				bad[EVO_CAN_BAD_OVERLONG]++;
		} else if (res == EVO_SLCAN_BAD) {
			bad[slcan_bad(s, n, wb)]++;
		}
		return;
	}
	case 'T': case 'r': case 'R': case 'd': case 'D': case 'b': case 'B':
		bad[EVO_CAN_BAD_NOT_OURS]++; /* extended, remote, FD */
		return;
	case 'z': case 'Z':
		if (!r->as_adapter && n == 1)
			return; /* an adapter's "sent" acknowledgement */
		break;
	default:
		break;
	}
	if (r->as_adapter && strchr("COSsVvNFXLWUM", s[0])) {
		/* a command to the adapter evo stands for: done */
		answer(s[0] == 'V'   ? "V1013\r"
		       : s[0] == 'N' ? "NEVO0\r"
				     : "\r",
		       reply, cap, reply_len);
		return;
	}
	bad[EVO_CAN_BAD_SYNTAX]++;
}

void evo_slcan_read(evo_slcan_reader *r, const char *b, size_t n,
		    evo_can_frame *out, int max, int *got, unsigned long *bad,
		    char *reply, size_t cap, size_t *reply_len)
{
	*got = 0;
	for (size_t i = 0; i < n; i++) {
		char ch = b[i];
		if (ch == '\a') {
			bad[EVO_CAN_BAD_REPLY]++;
			continue;
		}
		if (ch == '\r' || ch == '\n') {
			if (r->overlong)
				bad[EVO_CAN_BAD_OVERLONG]++;
			else
				slcan_line(r, r->line, r->n, out, max, got, bad,
					   reply, cap, reply_len);
			r->n = 0;
			r->overlong = 0;
			continue;
		}
		if (r->n < EVO_SLCAN_HOST_LINE)
			r->line[r->n++] = ch;
		else
			r->overlong = 1;
	}
}
