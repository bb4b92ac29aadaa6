/* evo — the mind image: the binary form of a mind model.
 *
 * Little-endian, every section 4-byte aligned. A header, then sections:
 *   variables  n_vars bytes, evo_var_type each (padded to 4)
 *   skills     n_skills evo_image_skill, top-down, master first
 *   io         n_io evo_image_io: each skill's inputs then outputs
 *   nets       n_nets evo_image_net, with their nodes, links and outputs
 *   names      sensors, actuators, variables, skills: NUL-terminated
 *              strings in that order (for people and tools; the tick
 *              never reads them)
 * The CRC-32 (IEEE 802.3) covers every byte after the crc field. The
 * names hash is evo_names_hash over the sensor, actuator and variable
 * names, so an image only runs with the botdesc and vardesc it was built
 * for. docs/mind-image.md is the reference. */
#ifndef EVO_IMAGE_H
#define EVO_IMAGE_H

#include <stddef.h>
#include <stdint.h>

#include "evo/formats.h"
#include "evo/status.h"

#define EVO_IMAGE_MAGIC 0x4D4F5645u /* "EVOM" */
#define EVO_IMAGE_VERSION 1u

typedef struct evo_image_header {
	uint32_t magic;
	uint16_t version;
	uint16_t header_size; /* sizeof(evo_image_header) */
	uint32_t length;      /* whole image, bytes */
	uint32_t crc;	      /* CRC-32 of bytes [16, length) */
	uint32_t names_hash;
	uint16_t n_sensors, n_actuators;
	uint16_t n_vars, n_skills;
	uint16_t n_io, n_nets;
	uint32_t off_vars, off_skills, off_io, off_nets, off_names;
	uint32_t names_len;
} evo_image_header;

typedef struct evo_image_skill {
	uint16_t in_start, n_in;   /* into io[] */
	uint16_t out_start, n_out; /* into io[] */
	uint8_t kind;		   /* evo_skill_kind */
	uint8_t pad;
	uint16_t slot;	   /* neural: net index; hard-coded: its ordinal */
	uint32_t hc_class; /* hard-coded: evo_name_hash of the class name */
} evo_image_skill;

typedef struct evo_image_io {
	uint8_t type; /* evo_input_type or evo_output_type */
	uint8_t pad;
	uint16_t index; /* sensor, actuator, variable or skill index */
} evo_image_io;

typedef struct evo_image_net {
	uint16_t n_in, n_out, n_nodes, n_links;
	uint32_t off_nodes, off_links, off_out; /* from the image start */
	uint32_t persist; /* recurrent: offset in the state's persistent
			     activations, words; 0xFFFFFFFF: feed-forward */
} evo_image_net;

/* FNV-1a, 32 bits, of a NUL-terminated string. */
uint32_t evo_name_hash(const char *s);

/* CRC-32 (IEEE 802.3, reflected, as zlib computes it). Start with crc 0;
 * feed pieces in order. */
uint32_t evo_crc32(uint32_t crc, const void *data, size_t len);

/* The hash an image built for these names carries: FNV-1a over the
 * sensor, actuator and variable names in order, each followed by a NUL,
 * with a 0x1E byte between the three lists. */
uint32_t evo_names_hash(const char *const *sensors, unsigned n_sensors,
			const char *const *actuators, unsigned n_actuators,
			const char *const *vars, unsigned n_vars);

/* ---- writing ------------------------------------------------------ */

/* A skill ready to be written: names already resolved to indices. */
typedef struct evo_build_skill {
	const char *name;
	uint8_t kind; /* evo_skill_kind */
	uint16_t n_in, n_out;
	const evo_image_io *in, *out; /* SK index: position in build order */
	const evo_netdesc *net;	      /* neural */
	const char *hc_class;	      /* hard-coded */
} evo_build_skill;

typedef struct evo_build {
	uint16_t n_sensors, n_actuators, n_vars, n_skills;
	const char *const *sensor_name;
	const char *const *actuator_name;
	const char *const *var_name;
	const uint8_t *var_type;
	const evo_build_skill *skill; /* top-down, master first */
} evo_build;

/* Write the image of b into buf (4-byte aligned, cap bytes). *len gets the
 * image's size, also when buf is too small (then EVO_ERR_NOMEM), so a
 * caller can ask with cap 0 first. ws is scratch for compiling networks.
 * The result is not validated beyond what writing needs: open it with
 * evo_mind_open. */
struct evo_net_compile_ws;
evo_status evo_image_write(const evo_build *b, struct evo_net_compile_ws *ws,
			   void *buf, size_t cap, size_t *len);

#endif
