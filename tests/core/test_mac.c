/* SHA-256 and HMAC-SHA-256 (core/src/mac.c) against the published test
 * vectors: FIPS 180-4's examples (NIST's "Example Algorithms" document) and
 * RFC 4231's HMAC-SHA-256 test cases, keys longer than a block included.
 * The digests below are copied from those documents, not from evo. */
#include <stdio.h>

#include "evo/mac.h"
#include "harness.h"

static void hex(const uint8_t *d, char out[65])
{
	static const char digits[] = "0123456789abcdef";
	for (unsigned i = 0; i < 32; i++) {
		out[2 * i] = digits[d[i] >> 4];
		out[2 * i + 1] = digits[d[i] & 15];
	}
	out[64] = 0;
}

static int sha_is(const void *msg, size_t n, const char *want)
{
	evo_sha256 c;
	uint8_t d[32];
	char got[65];
	evo_sha256_init(&c);
	evo_sha256_update(&c, msg, n);
	evo_sha256_final(&c, d);
	hex(d, got);
	if (strcmp(got, want) != 0) {
		printf("    got  %s\n    want %s\n", got, want);
		return 0;
	}
	return 1;
}

static int hmac_is(const void *key, size_t kn, const void *msg, size_t n,
		   const char *want)
{
	uint8_t d[32];
	char got[65];
	evo_hmac_sha256(key, kn, msg, n, d);
	hex(d, got);
	if (strcmp(got, want) != 0) {
		printf("    got  %s\n    want %s\n", got, want);
		return 0;
	}
	return 1;
}

TEST(sha256_fips_examples)
{
	CHECK(sha_is("abc", 3,
		     "ba7816bf8f01cfea414140de5dae2223"
		     "b00361a396177a9cb410ff61f20015ad"));
	CHECK(sha_is("", 0,
		     "e3b0c44298fc1c149afbf4c8996fb924"
		     "27ae41e4649b934ca495991b7852b855"));
	const char *two = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
	CHECK(sha_is(two, strlen(two),
		     "248d6a61d20638b8e5c026930c3e6039"
		     "a33ce45964ff2167f6ecedd419db06c1"));
}

/* One million 'a's fed in pieces of odd sizes: the block buffering across
 * calls must give the digest of the whole. */
TEST(sha256_million_a_in_pieces)
{
	static uint8_t a[997];
	memset(a, 'a', sizeof a);
	evo_sha256 c;
	evo_sha256_init(&c);
	size_t left = 1000000, step = 1;
	while (left > 0) {
		size_t n = step < left ? step : left;
		evo_sha256_update(&c, a, n);
		left -= n;
		step = step * 7 % sizeof a + 1;
	}
	uint8_t d[32];
	char got[65];
	evo_sha256_final(&c, d);
	hex(d, got);
	CHECK(strcmp(got, "cdc76e5c9914fb9281a1c7e284d73e67"
			  "f1809a48a497200e046d39ccc7112cd0") == 0);
}

TEST(hmac_rfc4231)
{
	uint8_t k20[20], k131[131], d50[50];
	memset(k20, 0x0b, sizeof k20);
	CHECK(hmac_is(k20, 20, "Hi There", 8,
		      "b0344c61d8db38535ca8afceaf0bf12b"
		      "881dc200c9833da726e9376c2e32cff7"));
	CHECK(hmac_is("Jefe", 4, "what do ya want for nothing?", 28,
		      "5bdcc146bf60754e6a042426089575c7"
		      "5a003f089d2739839dec58b964ec3843"));
	memset(k20, 0xaa, sizeof k20);
	memset(d50, 0xdd, sizeof d50);
	CHECK(hmac_is(k20, 20, d50, 50,
		      "773ea91e36800e46854db8ebd09181a7"
		      "2959098b3ef8c122d9635514ced565fe"));
	uint8_t k25[25];
	for (unsigned i = 0; i < 25; i++)
		k25[i] = (uint8_t)(i + 1);
	memset(d50, 0xcd, sizeof d50);
	CHECK(hmac_is(k25, 25, d50, 50,
		      "82558a389a443c0ea4cc819899f2083a"
		      "85f0faa3e578f8077a2e3ff46729665b"));
	memset(k131, 0xaa, sizeof k131);
	const char *t6 = "Test Using Larger Than Block-Size Key - Hash Key First";
	CHECK(hmac_is(k131, 131, t6, strlen(t6),
		      "60e431591ee0b67f0d8a26aacbf5b77f"
		      "8e0bc6213728c5140546040f0ee37f54"));
	const char *t7 = "This is a test using a larger than block-size key "
			 "and a larger than block-size data. The key needs to "
			 "be hashed before being used by the HMAC algorithm.";
	CHECK(hmac_is(k131, 131, t7, strlen(t7),
		      "9b09ffa71b942fcb27635fbcd5b0e944"
		      "bfdc63644f0713938a7f51535c3a35e2"));
}

/* The MAC of a message given in pieces is the MAC of the whole. */
TEST(hmac_in_steps_equals_one_call)
{
	uint8_t one[32], steps[32];
	const char *msg = "name=corridor session=7 episode=3 tick=1200";
	evo_hmac_sha256("key", 3, msg, strlen(msg), one);
	evo_hmac c;
	evo_hmac_init(&c, "key", 3);
	for (size_t i = 0; i < strlen(msg); i += 5)
		evo_hmac_update(&c, msg + i, strlen(msg) - i < 5 ? strlen(msg) - i : 5);
	evo_hmac_final(&c, steps);
	CHECK(memcmp(one, steps, 32) == 0);
}

TEST(mac_equal)
{
	uint8_t a[32] = { 0 }, b[32] = { 0 };
	CHECK(evo_mac_equal(a, b, 32));
	b[31] = 1;
	CHECK(!evo_mac_equal(a, b, 32));
	CHECK(evo_mac_equal(a, b, 31));
	b[0] = 0x80;
	CHECK(!evo_mac_equal(a, b, 1));
	CHECK(evo_mac_equal(a, b, 0));
	CHECK_EQ_INT(evo_mac_equal(a, a, 32), 1);
}

int main(void)
{
	RUN(sha256_fips_examples);
	RUN(sha256_million_a_in_pieces);
	RUN(hmac_rfc4231);
	RUN(hmac_in_steps_equals_one_call);
	RUN(mac_equal);
	return test_summary();
}
