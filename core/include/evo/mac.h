/* SHA-256 (FIPS 180-4) and HMAC-SHA-256 (RFC 2104): the message
 * authentication of evo's remote protocol over LCM (docs/remote.md) and of
 * flash transfers over CAN (docs/wire.md). Freestanding: no allocation, the
 * caller owns every context; the firmware links it as the host does. */
#ifndef EVO_MAC_H
#define EVO_MAC_H

#include <stddef.h>
#include <stdint.h>

#define EVO_SHA256_BYTES 32u
#define EVO_SHA256_BLOCK 64u

typedef struct evo_sha256 {
	uint32_t h[8];
	uint64_t bytes;                /* message length so far */
	uint8_t block[EVO_SHA256_BLOCK];
	uint32_t fill;                 /* bytes waiting in block, < 64 */
} evo_sha256;

void evo_sha256_init(evo_sha256 *c);
/* Adds n bytes of data (data may be NULL when n is 0). */
void evo_sha256_update(evo_sha256 *c, const void *data, size_t n);
/* Writes the 32-byte digest; c must be initialised again before reuse. */
void evo_sha256_final(evo_sha256 *c, uint8_t out[EVO_SHA256_BYTES]);

/* HMAC-SHA-256 in steps, for a MAC over fields that are not contiguous in
 * memory. A key longer than 64 bytes is hashed first, as RFC 2104 says. */
typedef struct evo_hmac {
	evo_sha256 inner;
	uint8_t opad_key[EVO_SHA256_BLOCK];
} evo_hmac;

void evo_hmac_init(evo_hmac *c, const void *key, size_t key_len);
void evo_hmac_update(evo_hmac *c, const void *data, size_t n);
void evo_hmac_final(evo_hmac *c, uint8_t out[EVO_SHA256_BYTES]);

/* The whole MAC of one buffer in one call. */
void evo_hmac_sha256(const void *key, size_t key_len, const void *msg,
		     size_t n, uint8_t out[EVO_SHA256_BYTES]);

/* 1 when the n bytes of a and b are equal, else 0, in a time that does not
 * depend on where they differ (a MAC check must not tell a forger how many
 * leading bytes it guessed right). */
int evo_mac_equal(const void *a, const void *b, size_t n);

#endif
