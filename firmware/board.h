/* The board layer: what the firmware's main loop needs from a board. One
 * file per board implements it (board_microbit.c, board_mps2_an385.c);
 * cortex_m.c has what every Cortex-M board shares (startup, the
 * millisecond clock, semihosting). */
#ifndef EVO_FW_BOARD_H
#define EVO_FW_BOARD_H

#include <stdint.h>

#include "evo/fixed.h"

/* The board's name, e.g. "microbit (Cortex-M0)". */
extern const char board_name[];

/* Clocks, the serial line; called once, first thing in main. */
void board_init(void);

/* A byte received on the serial line, or -1 when none is waiting. Bytes
 * arrive by interrupt into a ring buffer; when it is full the board
 * leaves them in the UART, which holds the sender back. */
int board_getc(void);

/* Sleep until an interrupt (a received byte, or the millisecond clock)
 * unless a byte is already waiting. */
void board_idle(void);

/* Send a byte on the serial line; waits while the transmitter is busy. */
void board_putc(uint8_t c);

/* Milliseconds since board_init, from a hardware counter (not counted
 * interrupts, which a busy emulator host loses); wraps after 49 days. */
uint32_t board_millis(void);

/* Drive the actuators: n commands, Q16 in [0, 1], 0.5 neutral. The QEMU
 * boards have no motors: the commands go out only on the wire. */
void board_actuate(const evo_q16 *commands, unsigned n);

/* The flash of the mind slots, BOARD_FLASH_PAGE bytes a page, as NOR
 * flash behaves: erase sets a whole page to 0xFF, programming a word only
 * clears bits. Erase the page at addr (page-aligned); program the word at
 * addr (4-byte aligned). Both wait until the flash is done: on a real part
 * the core stalls meanwhile (docs/firmware.md, "Sending a mind"). */
#define BOARD_FLASH_PAGE 1024u
void board_flash_erase(uint32_t addr);
void board_flash_write(uint32_t addr, uint32_t word);

/* Stop with an exit status (under QEMU, the emulator's exit status). */
__attribute__((noreturn)) void board_exit(int status);

/* ---- shared by the Cortex-M boards (cortex_m.c) ---------------------- */

/* Start SysTick at 1 kHz from a core clock of cpu_hz: it wakes
 * board_idle every millisecond. */
void cortex_m_start_clock(uint32_t cpu_hz);

/* board_millis from a board's free-running counter: count is its value
 * now (counting up, wrapping at 2^32), per_ms its counts a millisecond. */
uint32_t cortex_m_millis(uint32_t count, uint32_t per_ms);

/* The boards' receive ring: bytes the UART interrupt took, not yet read. */
#define BOARD_RX_RING 256u /* a power of two */
typedef struct board_ring {
	volatile uint8_t buf[BOARD_RX_RING];
	volatile uint32_t head, tail; /* head: next write; tail: next read */
} board_ring;

static inline int board_ring_full(const board_ring *r)
{
	return r->head - r->tail == BOARD_RX_RING;
}

static inline void board_ring_put(board_ring *r, uint8_t c)
{
	r->buf[r->head % BOARD_RX_RING] = c;
	r->head++;
}

/* A byte, or -1 when empty. */
static inline int board_ring_get(board_ring *r)
{
	if (r->head == r->tail)
		return -1;
	int c = r->buf[r->tail % BOARD_RX_RING];
	r->tail++;
	return c;
}

/* Interrupts off and on (PRIMASK), and the race-free sleep: with
 * interrupts off, look for work, then WFI (which still wakes on a pending
 * interrupt), then interrupts on. */
static inline void cortex_m_irq_off(void)
{
	__asm__ volatile("cpsid i" ::: "memory");
}

static inline void cortex_m_irq_on(void)
{
	__asm__ volatile("cpsie i" ::: "memory");
}

static inline void cortex_m_wfi(void)
{
	__asm__ volatile("wfi" ::: "memory");
}

/* Enable external interrupt irq in the NVIC. */
void cortex_m_enable_irq(unsigned irq);

/* What the boards' external interrupts call (the vector table sends every
 * one of them here). */
void board_irq(void);

/* Semihosting SYS_EXIT_EXTENDED: QEMU exits with status. */
__attribute__((noreturn)) void cortex_m_semihost_exit(int status);

#endif
