/* evo — status codes.
 *
 * One list generates both the codes and their messages, so the two cannot
 * drift apart. Every core function that can fail returns an evo_status. */
#ifndef EVO_STATUS_H
#define EVO_STATUS_H

#define EVO_STATUS_LIST(X)                                                     \
	X(EVO_OK, "ok")                                                        \
	X(EVO_ERR_SYNTAX, "syntax error")                                      \
	X(EVO_ERR_NAME, "unknown name")                                        \
	X(EVO_ERR_COUNT, "count does not match its lines")                     \
	X(EVO_ERR_LIMIT, "a size limit was exceeded")                          \
	X(EVO_ERR_CYCLE, "skills form a cycle")                                \
	X(EVO_ERR_MISSING, "a required item is missing")                       \
	X(EVO_ERR_NOMEM, "the buffer given is too small")                      \
	X(EVO_ERR_IMAGE_MAGIC, "not a mind image (bad magic)")                 \
	X(EVO_ERR_IMAGE_VERSION, "mind image format version not supported")    \
	X(EVO_ERR_IMAGE_LENGTH, "mind image is truncated or has a bad length") \
	X(EVO_ERR_IMAGE_CRC, "mind image is corrupt (CRC-32 mismatch)")        \
	X(EVO_ERR_IMAGE_NAMES,                                                 \
	  "mind image was built for other sensors, actuators or variables")    \
	X(EVO_ERR_IMAGE_LAYOUT, "mind image has an invalid section layout")    \
	X(EVO_ERR_IMAGE_CLASS,                                                 \
	  "mind image uses a hard-coded skill class this build lacks")         \
	X(EVO_ERR_ALIGN, "buffer is not 4-byte aligned")                       \
	X(EVO_ERR_IMAGE_RANGE,                                                 \
	  "mind image has a network weight or bias out of range")

typedef enum evo_status {
#define EVO_STATUS_ENUM(code, text) code,
	EVO_STATUS_LIST(EVO_STATUS_ENUM)
#undef EVO_STATUS_ENUM
		EVO_STATUS_COUNT
} evo_status;

/* The message for a status code; never NULL. */
const char *evo_status_str(evo_status s);

#endif
