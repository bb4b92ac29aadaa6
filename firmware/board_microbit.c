/* Board layer for QEMU's microbit: an nRF51822, Cortex-M0 at 16 MHz, its
 * UART on QEMU's first serial port, the UART's interrupt IRQ 2. */
#include "board.h"

const char board_name[] = "microbit (Cortex-M0)";

#define CPU_HZ	      16000000u
#define UART	      0x40002000u
#define UART_IRQ      2u
#define REG(off)      (*(volatile uint32_t *)(UART + (off)))
#define TASKS_STARTRX REG(0x000u)
#define TASKS_STARTTX REG(0x008u)
#define EVENTS_RXDRDY REG(0x108u)
#define EVENTS_TXDRDY REG(0x11Cu)
#define UART_INTENSET REG(0x304u)
#define UART_INTENCLR REG(0x308u)
#define UART_ENABLE   REG(0x500u)
#define UART_RXD      REG(0x518u)
#define UART_TXD      REG(0x51Cu)
#define UART_BAUDRATE REG(0x524u)
#define INT_RXDRDY    4u

/* TIMER0, a 32-bit counter at 1 MHz (16 MHz / 2^4): the millisecond
 * clock. CAPTURE[0] copies the count into CC[0]. */
#define TIMER0		0x40008000u
#define TREG(off)	(*(volatile uint32_t *)(TIMER0 + (off)))
#define TIMER_START	TREG(0x000u)
#define TIMER_CAPTURE0	TREG(0x040u)
#define TIMER_MODE	TREG(0x504u)
#define TIMER_BITMODE	TREG(0x508u)
#define TIMER_PRESCALER TREG(0x510u)
#define TIMER_CC0	TREG(0x540u)

static board_ring rx;

void board_init(void)
{
	UART_BAUDRATE = 0x01D7E000u; /* 115200 */
	UART_ENABLE = 4u;
	TASKS_STARTTX = 1u;
	TASKS_STARTRX = 1u;
	UART_INTENSET = INT_RXDRDY;
	cortex_m_enable_irq(UART_IRQ);
	TIMER_MODE = 0u;      /* timer, not counter */
	TIMER_BITMODE = 3u;   /* 32 bits */
	TIMER_PRESCALER = 4u; /* 1 MHz */
	TIMER_START = 1u;
	cortex_m_start_clock(CPU_HZ);
}

uint32_t board_millis(void)
{
	TIMER_CAPTURE0 = 1u;
	return cortex_m_millis(TIMER_CC0, 1000u);
}

/* Move what the UART's FIFO holds into the ring while there is room.
 * RXDRDY is a level while the FIFO holds bytes, so with the ring full the
 * interrupt is masked until board_getc makes room. */
static void drain(void)
{
	while (EVENTS_RXDRDY) {
		if (board_ring_full(&rx)) {
			UART_INTENCLR = INT_RXDRDY;
			return;
		}
		EVENTS_RXDRDY = 0; /* before reading RXD, as the manual says */
		board_ring_put(&rx, (uint8_t)UART_RXD);
	}
}

void board_irq(void)
{
	drain();
}

int board_getc(void)
{
	int c = board_ring_get(&rx);
	if (c < 0) {
		cortex_m_irq_off();
		drain();
		UART_INTENSET = INT_RXDRDY;
		cortex_m_irq_on();
		c = board_ring_get(&rx);
	}
	return c;
}

void board_idle(void)
{
	cortex_m_irq_off();
	if (rx.head == rx.tail && !EVENTS_RXDRDY)
		cortex_m_wfi();
	cortex_m_irq_on();
}

void board_putc(uint8_t c)
{
	UART_TXD = c;
	while (!EVENTS_TXDRDY)
		;
	EVENTS_TXDRDY = 0;
}

void board_actuate(const evo_q16 *commands, unsigned n)
{
	(void)commands;
	(void)n;
}

/* The NVMC programs and erases the nRF51's flash: CONFIG says which
 * (1 write, 2 erase, 0 read only), READY when it is done. */
#define NVMC	       0x4001E000u
#define NVMC_READY     (*(volatile uint32_t *)(NVMC + 0x400u))
#define NVMC_CONFIG    (*(volatile uint32_t *)(NVMC + 0x504u))
#define NVMC_ERASEPAGE (*(volatile uint32_t *)(NVMC + 0x508u))

static void nvmc_config(uint32_t mode)
{
	NVMC_CONFIG = mode;
	while (!(NVMC_READY & 1u))
		;
}

void board_flash_erase(uint32_t addr)
{
	nvmc_config(2u);
	NVMC_ERASEPAGE = addr;
	while (!(NVMC_READY & 1u))
		;
	nvmc_config(0u);
}

void board_flash_write(uint32_t addr, uint32_t word)
{
	nvmc_config(1u);
	*(volatile uint32_t *)addr = word;
	while (!(NVMC_READY & 1u))
		;
	nvmc_config(0u);
}

void board_exit(int status)
{
	cortex_m_semihost_exit(status);
}
