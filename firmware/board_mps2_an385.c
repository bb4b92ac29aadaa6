/* Board layer for QEMU's mps2-an385: a Cortex-M3 at 25 MHz, UART0 a CMSDK
 * APB UART (QEMU's first serial port), its receive interrupt IRQ 0, TIMER0
 * the millisecond clock. */
#include "board.h"

const char board_name[] = "mps2-an385 (Cortex-M3)";

#define CPU_HZ	       25000000u
#define UART0	       0x40004000u
#define UART_IRQ       0u
#define UART_DATA      (*(volatile uint32_t *)(UART0 + 0x000u))
#define UART_STATE     (*(volatile uint32_t *)(UART0 + 0x004u))
#define UART_CTRL      (*(volatile uint32_t *)(UART0 + 0x008u))
#define UART_INTCLEAR  (*(volatile uint32_t *)(UART0 + 0x00Cu))
#define UART_BAUDDIV   (*(volatile uint32_t *)(UART0 + 0x010u))
#define STATE_TXFULL   1u
#define STATE_RXFULL   2u
#define CTRL_TX_EN     1u
#define CTRL_RX_EN     2u
#define CTRL_RX_INT_EN 8u
#define INT_RX	       2u

/* TIMER0, a CMSDK APB timer: a 32-bit down counter at the 25 MHz system
 * clock, the millisecond clock. */
#define TIMER0	     0x40000000u
#define TIMER_CTRL   (*(volatile uint32_t *)(TIMER0 + 0x000u))
#define TIMER_VALUE  (*(volatile uint32_t *)(TIMER0 + 0x004u))
#define TIMER_RELOAD (*(volatile uint32_t *)(TIMER0 + 0x008u))
#define TIMER_ENABLE 1u

static board_ring rx;

void board_init(void)
{
	UART_BAUDDIV = CPU_HZ / 115200u; /* QEMU needs it >= 16 to send */
	UART_CTRL = CTRL_TX_EN | CTRL_RX_EN | CTRL_RX_INT_EN;
	cortex_m_enable_irq(UART_IRQ);
	TIMER_RELOAD = 0xFFFFFFFFu;
	TIMER_VALUE = 0xFFFFFFFFu;
	TIMER_CTRL = TIMER_ENABLE;
	cortex_m_start_clock(CPU_HZ);
}

uint32_t board_millis(void)
{
	/* counting down: its complement counts up */
	return cortex_m_millis(~TIMER_VALUE, CPU_HZ / 1000u);
}

/* Move what the UART holds into the ring while there is room. A byte left
 * in the UART (ring full) holds the sender back until board_getc takes
 * it. */
static void drain(void)
{
	while ((UART_STATE & STATE_RXFULL) && !board_ring_full(&rx))
		board_ring_put(&rx, (uint8_t)UART_DATA);
}

void board_irq(void)
{
	UART_INTCLEAR = INT_RX;
	drain();
}

int board_getc(void)
{
	int c = board_ring_get(&rx);
	if (c < 0) {
		cortex_m_irq_off();
		drain();
		cortex_m_irq_on();
		c = board_ring_get(&rx);
	}
	return c;
}

void board_idle(void)
{
	cortex_m_irq_off();
	if (rx.head == rx.tail && !(UART_STATE & STATE_RXFULL))
		cortex_m_wfi();
	cortex_m_irq_on();
}

void board_putc(uint8_t c)
{
	while (UART_STATE & STATE_TXFULL)
		;
	UART_DATA = c;
}

void board_actuate(const evo_q16 *commands, unsigned n)
{
	(void)commands;
	(void)n;
}

/* QEMU's AN385 has SRAM where the STM32F103 this build stands for has
 * flash, so a store writes it. The NOR rules are kept (erase to 0xFF,
 * programming only clears bits) so that the firmware behaves as on the
 * part, whose flash controller would be unlocked (FLASH_KEYR) and driven
 * a page (PER) or a half-word (PG) at a time. */
void board_flash_erase(uint32_t addr)
{
	volatile uint32_t *p = (volatile uint32_t *)addr;
	for (unsigned i = 0; i < BOARD_FLASH_PAGE / 4u; i++)
		p[i] = 0xFFFFFFFFu;
}

void board_flash_write(uint32_t addr, uint32_t word)
{
	volatile uint32_t *p = (volatile uint32_t *)addr;
	*p &= word;
}

void board_exit(int status)
{
	cortex_m_semihost_exit(status);
}
