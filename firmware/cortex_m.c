/* What every Cortex-M board shares: the vector table, the reset handler
 * (copy .data, zero .bss, call main), SysTick waking the main loop, the
 * millisecond clock from a board's counter, and
 * semihosting's exit. ARMv6-M code, so it runs on the M0(+) and the M3. */
#include <stddef.h>
#include <stdint.h>

#include "board.h"

int main(void);
void Reset_Handler(void);
void HardFault_Handler(void);
void SysTick_Handler(void);
void Default_Handler(void);

/* From the linker script. */
extern uint32_t __data_load[], __data_start[], __data_end[];
extern uint32_t __bss_start[], __bss_end[], __stack_top[];

void IRQ_Handler(void);
#define IRQ8                                                                   \
	IRQ_Handler, IRQ_Handler, IRQ_Handler, IRQ_Handler, IRQ_Handler,       \
		IRQ_Handler, IRQ_Handler, IRQ_Handler

/* Cortex-M system exceptions, then 32 external interrupts, all of which go
 * to the board's board_irq. */
__attribute__((section(".vectors"), used)) static void (*const vectors[48])(
	void) = {
	(void (*)(void))(uintptr_t)__stack_top,
	Reset_Handler,
	Default_Handler,   /* NMI */
	HardFault_Handler, /* HardFault */
	Default_Handler,   /* MemManage (M3) */
	Default_Handler,   /* BusFault (M3) */
	Default_Handler,   /* UsageFault (M3) */
	0,
	0,
	0,
	0,
	Default_Handler, /* SVCall */
	Default_Handler, /* DebugMon (M3) */
	0,
	Default_Handler, /* PendSV */
	SysTick_Handler,
	IRQ8, IRQ8, IRQ8, IRQ8,
};

void IRQ_Handler(void)
{
	board_irq();
}

#define NVIC_ISER (*(volatile uint32_t *)0xE000E100u)

void cortex_m_enable_irq(unsigned irq)
{
	NVIC_ISER = 1u << irq;
}

void Reset_Handler(void)
{
	uint32_t *src = __data_load, *dst = __data_start;
	while (dst < __data_end)
		*dst++ = *src++;
	for (dst = __bss_start; dst < __bss_end;)
		*dst++ = 0;
	main();
	board_exit(1);
}

/* A fault is a firmware bug: say so and stop with its own status. */
void HardFault_Handler(void)
{
	static const char msg[] = "# evo firmware: hard fault\r\n";
	for (const char *p = msg; *p; p++)
		board_putc((uint8_t)*p);
	board_exit(9);
}

void Default_Handler(void)
{
	HardFault_Handler();
}

/* SysTick only wakes the main loop from board_idle, every millisecond, so
 * that it sees its timeouts come; it does not count the time. */
void SysTick_Handler(void)
{
}

/* The milliseconds of board_millis, from a free-running counter of the
 * board's that counts `per_ms` a millisecond. A clock that counted SysTick
 * interrupts lost every one that came while another was still pending:
 * under QEMU on a busy host, where the emulator is off the CPU for tens of
 * milliseconds at a time, it ran at a third of the wall clock, and the
 * robot's 3 s transfer timeout took longer than evo flash waits for it
 * (docs/firmware.md). The counter's hardware keeps the time whatever the
 * interrupts do; only its difference since the last call is used, so it
 * may wrap, if it is read at least once a wrap. Main loop only. */
uint32_t cortex_m_millis(uint32_t count, uint32_t per_ms)
{
	static uint32_t last, sub, ms;
	sub += count - last;
	last = count;
	if (sub >= per_ms) {
		uint32_t k = sub / per_ms;
		ms += k;
		sub -= k * per_ms;
	}
	return ms;
}

#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)

void cortex_m_start_clock(uint32_t cpu_hz)
{
	SYST_RVR = cpu_hz / 1000u - 1u;
	SYST_CVR = 0;
	SYST_CSR = 7u; /* processor clock, interrupt, enable */
}

/* Semihosting: BKPT 0xAB with the operation in r0 and its argument in r1.
 * SYS_EXIT_EXTENDED (0x20) takes {reason, status}; QEMU exits with status
 * when the reason is ADP_Stopped_ApplicationExit (0x20026). */
void cortex_m_semihost_exit(int status)
{
	static uint32_t block[2];
	block[0] = 0x20026u;
	block[1] = (uint32_t)status;
	register uint32_t r0 __asm__("r0") = 0x20u;
	register uint32_t *r1 __asm__("r1") = block;
	__asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
	for (;;)
		;
}

/* The core and the main loop copy and clear memory; freestanding, so the
 * firmware brings its own. The loops are built with
 * -fno-tree-loop-distribute-patterns so GCC does not turn them back into
 * calls to themselves. */
void *memcpy(void *restrict dst, const void *restrict src, size_t n);
void *memset(void *dst, int c, size_t n);
void *memmove(void *dst, const void *src, size_t n);

void *memcpy(void *restrict dst, const void *restrict src, size_t n)
{
	uint8_t *d = dst;
	const uint8_t *s = src;
	while (n--)
		*d++ = *s++;
	return dst;
}

void *memmove(void *dst, const void *src, size_t n)
{
	uint8_t *d = dst;
	const uint8_t *s = src;
	if (d < s)
		while (n--)
			*d++ = *s++;
	else
		while (n--)
			d[n] = s[n];
	return dst;
}

void *memset(void *dst, int c, size_t n)
{
	uint8_t *d = dst;
	while (n--)
		*d++ = (uint8_t)c;
	return dst;
}
