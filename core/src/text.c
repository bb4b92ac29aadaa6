#include "text.h"

#include <limits.h>

size_t evo_txt_len(const char *s)
{
	size_t n = 0;
	while (s[n])
		n++;
	return n;
}

char evo_txt_upper(char c)
{
	return (c >= 'a' && c <= 'z') ? (char)(c - 'a' + 'A') : c;
}

int evo_txt_eq(const char *a, const char *b)
{
	while (*a && *a == *b) {
		a++;
		b++;
	}
	return *a == *b;
}

int evo_txt_ieq(const char *a, const char *b)
{
	while (*a && evo_txt_upper(*a) == evo_txt_upper(*b)) {
		a++;
		b++;
	}
	return evo_txt_upper(*a) == evo_txt_upper(*b);
}

int evo_txt_slice_eq(evo_txt_slice a, const char *b)
{
	size_t i;
	for (i = 0; i < a.len; i++)
		if (b[i] == 0 || a.s[i] != b[i])
			return 0;
	return b[i] == 0;
}

int evo_txt_slice_ieq(evo_txt_slice a, const char *b)
{
	size_t i;
	for (i = 0; i < a.len; i++)
		if (b[i] == 0 || evo_txt_upper(a.s[i]) != evo_txt_upper(b[i]))
			return 0;
	return b[i] == 0;
}

int evo_txt_copy(char *dst, size_t cap, evo_txt_slice s)
{
	size_t i, n = s.len < cap ? s.len : cap - 1;
	for (i = 0; i < n; i++)
		dst[i] = s.s[i];
	for (; i < cap; i++)
		dst[i] = 0;
	return s.len < cap ? 0 : -1;
}

/* ---- the formatter ------------------------------------------------ */

typedef struct out_buf {
	char *dst;
	size_t cap, n; /* n < cap always: room is kept for the NUL */
} out_buf;

static void put(out_buf *o, char c)
{
	if (o->n + 1 < o->cap)
		o->dst[o->n++] = c;
}

static void put_str(out_buf *o, const char *s)
{
	while (*s)
		put(o, *s++);
}

static void put_uint(out_buf *o, unsigned v)
{
	char digits[12];
	int i = 0;
	do {
		digits[i++] = (char)('0' + v % 10);
		v /= 10;
	} while (v);
	while (i)
		put(o, digits[--i]);
}

/* Input text is quoted back to the user, so it must stay readable: control
 * bytes become '?', and a long slice is cut at a UTF-8 character boundary
 * so the message never ends in half a character. */
static void put_quoted(out_buf *o, const char *s, size_t len)
{
	size_t i, n = len;
	int cut = 0;
	if (n > EVO_TXT_QUOTE_MAX) {
		n = EVO_TXT_QUOTE_MAX - 3;
		while (n > 0 && ((unsigned char)s[n] & 0xC0) == 0x80)
			n--;
		cut = 1;
	}
	for (i = 0; i < n; i++) {
		unsigned char c = (unsigned char)s[i];
		put(o, (c < 0x20 || c == 0x7F) ? '?' : (char)c);
	}
	if (cut)
		put_str(o, "...");
}

size_t evo_txt_vfmt(char *dst, size_t cap, const char *fmt, va_list ap)
{
	out_buf o;
	o.dst = dst;
	o.cap = cap;
	o.n = 0;
	if (cap == 0)
		return 0;
	while (*fmt) {
		char c = *fmt++;
		if (c != '%') {
			put(&o, c);
			continue;
		}
		c = *fmt++;
		if (c == 's') {
			const char *s = va_arg(ap, const char *);
			put_str(&o, s ? s : "(null)");
		} else if (c == 'd') {
			int v = va_arg(ap, int);
			if (v < 0) {
				put(&o, '-');
				put_uint(&o, 0u - (unsigned)v);
			} else {
				put_uint(&o, (unsigned)v);
			}
		} else if (c == 'u') {
			put_uint(&o, va_arg(ap, unsigned));
		} else if (c == 'c') {
			put(&o, (char)va_arg(ap, int));
		} else if (c == '.' && fmt[0] == '*' && fmt[1] == 's') {
			int n = va_arg(ap, int);
			const char *s = va_arg(ap, const char *);
			put_quoted(&o, s, n > 0 ? (size_t)n : 0);
			fmt += 2;
		} else if (c == '%') {
			put(&o, '%');
		} else {
			/* A bad format is a bug in evo: show it, don't guess.
			 */
			put(&o, '%');
			if (!c)
				break;
			put(&o, c);
		}
	}
	dst[o.n] = 0;
	return o.n;
}

size_t evo_txt_fmt(char *dst, size_t cap, const char *fmt, ...)
{
	va_list ap;
	size_t n;
	va_start(ap, fmt);
	n = evo_txt_vfmt(dst, cap, fmt, ap);
	va_end(ap);
	return n;
}

void evo_txt_diag(evo_diag *d, const char *file, uint32_t line, const char *fmt,
		  ...)
{
	va_list ap;
	size_t n;
	if (!d)
		return;
	n = evo_txt_fmt(d->msg, sizeof d->msg,
			"%s:%u: ", file ? file : "(input)", (unsigned)line);
	va_start(ap, fmt);
	evo_txt_vfmt(d->msg + n, sizeof d->msg - n, fmt, ap);
	va_end(ap);
}

/* ---- the lexer ---------------------------------------------------- */

enum { CH_OTHER, CH_BLANK, CH_EOL, CH_COLON, CH_CONTROL };

/* A CR before LF is a blank (CRLF files); a lone CR ends a line, as in old
 * Mac files. */
static int class_at(const evo_txt_lexer *lx, size_t p)
{
	unsigned char c = (unsigned char)lx->buf[p];
	if (c == ' ' || c == '\t' || c == '\v' || c == '\f')
		return CH_BLANK;
	if (c == '\n')
		return CH_EOL;
	if (c == '\r')
		return (p + 1 < lx->len && lx->buf[p + 1] == '\n') ? CH_BLANK
								   : CH_EOL;
	if (c == ':')
		return CH_COLON;
	if (c < 0x20 || c == 0x7F)
		return CH_CONTROL;
	return CH_OTHER;
}

void evo_txt_lex_init(evo_txt_lexer *lx, const char *buf, size_t len,
		      const char *file)
{
	lx->buf = buf;
	lx->len = buf ? len : 0;
	lx->pos = 0;
	lx->line = 1;
	lx->line_start = 1;
	lx->file = file;
	if (lx->len >= 3 && (unsigned char)buf[0] == 0xEF &&
	    (unsigned char)buf[1] == 0xBB && (unsigned char)buf[2] == 0xBF)
		lx->pos = 3;
}

static void bad_byte(const evo_txt_lexer *lx, evo_diag *err)
{
	evo_txt_diag(err, lx->file, lx->line,
		     "expected text, found a control byte (code %u); is this a "
		     "text file?",
		     (unsigned)(unsigned char)lx->buf[lx->pos]);
}

static void split_fields(evo_txt_entry *e)
{
	const char *s = e->text.s;
	size_t i = 0, n = e->text.len;
	e->n_fields = 0;
	for (;;) {
		size_t start, end;
		while (i < n && (s[i] == ' ' || s[i] == '\t'))
			i++;
		start = i;
		while (i < n && s[i] != ':')
			i++;
		end = i;
		while (end > start && (s[end - 1] == ' ' || s[end - 1] == '\t'))
			end--;
		if (e->n_fields < EVO_TXT_MAX_FIELDS) {
			e->field[e->n_fields].s = s + start;
			e->field[e->n_fields].len = end - start;
		}
		e->n_fields++;
		if (i >= n)
			break;
		i++; /* the ':' */
	}
}

int evo_txt_lex_next(evo_txt_lexer *lx, evo_txt_entry *e, evo_diag *err)
{
	size_t start, end;
	/* Skip blanks, line ends and comment lines to the next entry. */
	for (;;) {
		int k;
		if (lx->pos >= lx->len)
			return 0;
		k = class_at(lx, lx->pos);
		if (k == CH_EOL) {
			lx->line++;
			lx->line_start = 1;
			lx->pos++;
		} else if (k == CH_BLANK) {
			lx->pos++;
		} else if (lx->line_start && lx->buf[lx->pos] == '#') {
			while (lx->pos < lx->len &&
			       class_at(lx, lx->pos) != CH_EOL)
				lx->pos++;
		} else if (k == CH_CONTROL) {
			bad_byte(lx, err);
			return -1;
		} else {
			break;
		}
	}
	lx->line_start = 0;
	start = lx->pos;
	/* Words joined by ':' form one entry, blanks beside a ':' included. */
	for (;;) {
		int k;
		size_t j;
		if (lx->pos >= lx->len)
			break;
		k = class_at(lx, lx->pos);
		if (k == CH_OTHER) {
			lx->pos++;
			continue;
		}
		if (k == CH_CONTROL) {
			bad_byte(lx, err);
			return -1;
		}
		if (k == CH_COLON) {
			lx->pos++;
			while (lx->pos < lx->len &&
			       class_at(lx, lx->pos) == CH_BLANK)
				lx->pos++;
			continue;
		}
		if (k == CH_EOL)
			break;
		j = lx->pos;
		while (j < lx->len && class_at(lx, j) == CH_BLANK)
			j++;
		if (j < lx->len && lx->buf[j] == ':') {
			lx->pos = j;
			continue;
		}
		break;
	}
	end = lx->pos;
	while (end > start && class_at(lx, end - 1) == CH_BLANK)
		end--;
	e->text.s = lx->buf + start;
	e->text.len = end - start;
	e->line = lx->line;
	split_fields(e);
	return 1;
}

uint32_t evo_txt_lex_end_line(const evo_txt_lexer *lx)
{
	/* After a final newline the lexer is on an empty line past the end. */
	if (lx->line > 1 && lx->len > 0 &&
	    (lx->buf[lx->len - 1] == '\n' || lx->buf[lx->len - 1] == '\r'))
		return lx->line - 1;
	return lx->line;
}

evo_txt_slice evo_txt_rest(const evo_txt_entry *e, size_t i)
{
	evo_txt_slice r;
	const char *s = e->text.s, *end = e->text.s + e->text.len;
	size_t k = 0;
	/* Field i starts after the i-th ':'; blanks after it are skipped. */
	while (k < i && s < end) {
		if (*s == ':')
			k++;
		s++;
	}
	while (s < end && (*s == ' ' || *s == '\t'))
		s++;
	r.s = s;
	r.len = (size_t)(end - s);
	return r;
}

/* ---- numbers and names -------------------------------------------- */

int evo_txt_uint(evo_txt_slice s, uint32_t max, uint32_t *out)
{
	uint32_t v = 0;
	int big = 0;
	size_t i;
	if (s.len == 0)
		return -1;
	for (i = 0; i < s.len; i++) {
		unsigned d = (unsigned)(unsigned char)s.s[i] - '0';
		if (d > 9)
			return -1;
		if (d > max || v > (max - d) / 10)
			big = 1;
		else
			v = v * 10 + d;
	}
	if (big)
		return -2;
	*out = v;
	return 0;
}

unsigned evo_txt_distance(evo_txt_slice s, const char *b)
{
	/* One row of the DP table; names are short, so it fits the stack. */
	unsigned row[EVO_NAME_MAX + 1];
	size_t la = s.len < EVO_NAME_MAX ? s.len : EVO_NAME_MAX;
	size_t lb = evo_txt_len(b), i, j;
	if (lb > EVO_NAME_MAX)
		lb = EVO_NAME_MAX;
	for (j = 0; j <= lb; j++)
		row[j] = (unsigned)j;
	for (i = 1; i <= la; i++) {
		unsigned diag = row[0];
		row[0] = (unsigned)i;
		for (j = 1; j <= lb; j++) {
			unsigned up = row[j];
			unsigned best = diag + (evo_txt_upper(s.s[i - 1]) !=
						evo_txt_upper(b[j - 1]));
			if (up + 1 < best)
				best = up + 1;
			if (row[j - 1] + 1 < best)
				best = row[j - 1] + 1;
			row[j] = best;
			diag = up;
		}
	}
	return row[lb];
}

const char *evo_txt_closest(evo_txt_slice s, const char *const *list, size_t n)
{
	const char *best = NULL;
	unsigned best_d = UINT_MAX;
	size_t i;
	for (i = 0; n ? i < n : list[i] != NULL; i++) {
		unsigned d = evo_txt_distance(s, list[i]);
		if (d < best_d) {
			best_d = d;
			best = list[i];
		}
	}
	return best;
}

evo_status evo_txt_name(char *dst, evo_txt_slice f, const evo_txt_entry *e,
			const char *what, const char *file, evo_diag *err)
{
	if (f.len == 0) {
		evo_txt_diag(err, file, e->line, "expected %s, found '%.*s'",
			     what, EVO_TXT_Q(e->text));
		return EVO_ERR_SYNTAX;
	}
	if (f.len >= EVO_NAME_MAX) {
		evo_txt_diag(err, file, e->line,
			     "expected %s of at most %u bytes, found one of %u "
			     "bytes: '%.*s'",
			     what, (unsigned)(EVO_NAME_MAX - 1),
			     f.len > UINT_MAX ? UINT_MAX : (unsigned)f.len,
			     EVO_TXT_Q(f));
		return EVO_ERR_LIMIT;
	}
	evo_txt_copy(dst, EVO_NAME_MAX, f);
	return EVO_OK;
}

const char *evo_closest_name(const char *word, const char *const *list,
			     size_t n, unsigned *distance)
{
	evo_txt_slice w = {word, evo_txt_len(word)};
	const char *best = n ? evo_txt_closest(w, list, n) : NULL;
	if (distance)
		*distance = best ? evo_txt_distance(w, best) : UINT_MAX;
	return best;
}
