/* evo — the clocks the host's waits and real-time loops read. */
#ifndef EVO_CLOCK_H
#define EVO_CLOCK_H

/* Seconds on the monotonic clock (for periods and timeouts). */
double evo_clock_now(void);

/* Seconds on the real-time clock (to compare with a message's arrival
 * stamp). */
double evo_clock_real(void);

#endif
