/* evo's wire: frame layout and slcan lines (evo/wire.h). */
#include "evo/wire.h"

void evo_wire_pack(uint16_t base, const evo_q16 *values, unsigned n,
		   unsigned k, evo_can_frame *f)
{
	unsigned first = 2u * k;
	unsigned count = n - first >= 2u ? 2u : 1u;
	f->id = (uint16_t)(base + k);
	f->len = (uint8_t)(4u * count);
	for (unsigned i = 0; i < 8u; i++)
		f->data[i] = 0;
	for (unsigned i = 0; i < count; i++)
		evo_wire_put_u32(f->data + 4u * i, (uint32_t)values[first + i]);
}

int evo_wire_unpack(uint16_t base, const evo_can_frame *f, evo_q16 *values,
		    unsigned n)
{
	if (f->id < base || (unsigned)(f->id - base) >= evo_wire_frames(n))
		return -1 - (int)EVO_WIRE_BAD_ID;
	unsigned k = (unsigned)(f->id - base);
	unsigned count = n - 2u * k >= 2u ? 2u : 1u;
	if (f->len != 4u * count)
		return -1 - (int)EVO_WIRE_BAD_LENGTH;
	for (unsigned i = 0; i < count; i++)
		values[2u * k + i] = (evo_q16)evo_wire_get_u32(f->data + 4u * i);
	return (int)k;
}

void evo_slcan_rx_init(evo_slcan_rx *rx)
{
	rx->n = 0;
	rx->overlong = 0;
}

/* The value of a hex digit, or -1. */
static int hex_value(char c)
{
	if (c >= '0' && c <= '9')
		return c - '0';
	if (c >= 'A' && c <= 'F')
		return c - 'A' + 10;
	if (c >= 'a' && c <= 'f')
		return c - 'a' + 10;
	return -1;
}

evo_slcan_result evo_slcan_decode(const char *line, size_t n,
				  evo_can_frame *f, evo_wire_bad *bad)
{
	if (n == 0)
		return EVO_SLCAN_EMPTY;
	if (n > EVO_SLCAN_LINE_MAX) {
		*bad = EVO_WIRE_BAD_OVERLONG;
		return EVO_SLCAN_BAD;
	}
	/* Every character after the 't' must be a hex digit, whatever the
	 * length says: a line with a stray character is a syntax error
	 * before it is a length error. */
	if (line[0] != 't') {
		*bad = EVO_WIRE_BAD_SYNTAX;
		return EVO_SLCAN_BAD;
	}
	for (size_t i = 1; i < n; i++)
		if (hex_value(line[i]) < 0) {
			*bad = EVO_WIRE_BAD_SYNTAX;
			return EVO_SLCAN_BAD;
		}
	if (n < 5) { /* t, three id digits, the DLC */
		*bad = EVO_WIRE_BAD_LENGTH;
		return EVO_SLCAN_BAD;
	}
	unsigned id = (unsigned)(hex_value(line[1]) << 8 |
				 hex_value(line[2]) << 4 | hex_value(line[3]));
	unsigned len = (unsigned)hex_value(line[4]);
	if (id > 0x7FFu) {
		*bad = EVO_WIRE_BAD_ID;
		return EVO_SLCAN_BAD;
	}
	if (len > 8u || n != 5u + 2u * len) {
		*bad = EVO_WIRE_BAD_LENGTH;
		return EVO_SLCAN_BAD;
	}
	f->id = (uint16_t)id;
	f->len = (uint8_t)len;
	for (unsigned i = 0; i < 8u; i++)
		f->data[i] = i < len ? (uint8_t)(hex_value(line[5 + 2 * i]) << 4 |
						 hex_value(line[6 + 2 * i]))
				     : 0;
	return EVO_SLCAN_FRAME;
}

evo_slcan_result evo_slcan_rx_byte(evo_slcan_rx *rx, uint8_t c,
				   evo_can_frame *f, evo_wire_bad *bad)
{
	if (c == '\r' || c == '\n') {
		evo_slcan_result r;
		if (rx->overlong) {
			*bad = EVO_WIRE_BAD_OVERLONG;
			r = EVO_SLCAN_BAD;
		} else {
			r = evo_slcan_decode(rx->line, rx->n, f, bad);
		}
		evo_slcan_rx_init(rx);
		return r;
	}
	if (rx->overlong)
		return EVO_SLCAN_MORE;
	if (rx->n == EVO_SLCAN_LINE_MAX) {
		rx->overlong = 1;
		return EVO_SLCAN_MORE;
	}
	rx->line[rx->n++] = (char)c;
	return EVO_SLCAN_MORE;
}

size_t evo_slcan_encode(const evo_can_frame *f, char *buf)
{
	static const char hex[] = "0123456789ABCDEF";
	size_t n = 0;
	buf[n++] = 't';
	buf[n++] = hex[(f->id >> 8) & 0x7u];
	buf[n++] = hex[(f->id >> 4) & 0xFu];
	buf[n++] = hex[f->id & 0xFu];
	buf[n++] = hex[f->len & 0xFu];
	for (unsigned i = 0; i < f->len && i < 8u; i++) {
		buf[n++] = hex[f->data[i] >> 4];
		buf[n++] = hex[f->data[i] & 0xFu];
	}
	buf[n++] = '\r';
	return n;
}
