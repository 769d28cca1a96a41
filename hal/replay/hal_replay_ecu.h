/*
 * hal_replay_ecu.h - the ECU run over a replayed log (hal_replay.h) in
 * logical time: the same program on the host (sim_host/tools/pfe_ecu_replay.c) and on
 * the emulated Cortex-M4 (hal/mps2/main_ecu.c).
 *
 * The ECU starts at the first log frame's time with erased NVM and ticks
 * every PFE_ECU_TICK_US through hal_ecu_loop_step(); before each tick the
 * log frames due by then go on the bus. The run ends HAL_REPLAY_ECU_TAIL_US
 * after the last log frame, so that the record shows the inputs time out.
 * A silence in the log longer than HAL_REPLAY_ECU_GAP_US is crossed in one
 * jump (whole ticks, counted): the ECU's inputs are stale by then anyway,
 * and a log whose clock jumps by days must not tick for days.
 *
 * Memory: all in hal_replay_ecu_t (caller owned; 14 KiB on the Cortex-M4,
 * half of it the two receive queues of the bus).
 */
#ifndef HAL_REPLAY_ECU_H
#define HAL_REPLAY_ECU_H

#include <stdbool.h>
#include <stdint.h>

#include "firmware/pfe_ecu.h"
#include "hal/hal_ecu_loop.h"
#include "hal/replay/hal_replay.h"

#define HAL_REPLAY_ECU_TAIL_US 1000000U
#define HAL_REPLAY_ECU_GAP_US 10000000U
#define HAL_REPLAY_ECU_SUMMARY_MAX 512U  /* bytes of hal_replay_ecu_summary()'s text, NUL included */

typedef struct {
    hal_replay_bus_t bus;
    hal_nvm_t nvm;
    pfe_ecu_t ecu;
    hal_ecu_loop_t loop;
    hal_can_t *can;
    uint64_t now_us;                   /* the next tick's deadline */
    uint32_t ticks;
    uint32_t gaps_skipped;
    uint32_t frames_sent;
} hal_replay_ecu_t;

/* A run's options, as the host tool and the Cortex-M4 image both take them:
 *   --log LOG [--record OUT] [--address SA] [--save-interval-ms MS]
 *   [--vehicles N] [--position P] [--gap-cm D]
 * Numbers in decimal or 0x hex. Defaults: no record, address
 * PFE_ECU_DEFAULT_ADDRESS, save every 10 s, one truck, position 0, 10 m. */
typedef struct {
    const char *log_path;
    const char *record_path;           /* NULL: no record */
    pfe_ecu_config_t cfg;              /* hal_ecu_loop_config() of the options */
} hal_replay_ecu_args_t;

#define HAL_REPLAY_ECU_USAGE                                                                   \
    "--log LOG [--record OUT] [--address SA] [--save-interval-ms MS]"                        \
    " [--vehicles N] [--position P] [--gap-cm D]"

/* Parses argv[1] .. argv[argc - 1]. Returns 0; 1 for --help; -1 with a
 * one-line English reason in err (at most cap bytes with the NUL). The
 * strings stay argv's. */
int hal_replay_ecu_args(int argc, char *const argv[], hal_replay_ecu_args_t *out, char *err,
                        uint32_t cap);

/*
 * Opens the bus on the log (read) and the record (write, may be NULL), one
 * handle for the ECU, and starts the ECU with cfg. Returns PFE_OK;
 * HAL_ENODEV when the log holds no frame the bus can carry (the bus's
 * statistics say why); PFE_EINVAL for a configuration the ECU refuses.
 */
int hal_replay_ecu_init(hal_replay_ecu_t *run, hal_replay_read_fn read, void *read_ctx,
                        hal_replay_write_fn write, void *write_ctx, const pfe_ecu_config_t *cfg);

/* The same with the log's frames from source (hal_replay_init_source()),
 * as the host tool reads them (sim_host/lib/replay_source.h). */
int hal_replay_ecu_init_source(hal_replay_ecu_t *run, hal_replay_source_fn source, void *source_ctx,
                               hal_replay_write_fn write, void *write_ctx,
                               const pfe_ecu_config_t *cfg);

/* One tick: true, or false once the run is over (nothing done then).
 * The same as hal_replay_ecu_feed() then, if it returned true,
 * hal_replay_ecu_tick(). */
bool hal_replay_ecu_step(hal_replay_ecu_t *run);

/* The two halves of a step, for measuring them apart: feed puts the log
 * frames due by the next deadline on the bus (reading and parsing the log,
 * writing the record), false once the run is over; tick runs the ECU's
 * loop at that deadline (hal_ecu_loop_step()) and moves the deadline on. */
bool hal_replay_ecu_feed(hal_replay_ecu_t *run);
void hal_replay_ecu_tick(hal_replay_ecu_t *run);

/* Final NVM save and record flush: 0, or HAL_EIO if the record failed. */
int hal_replay_ecu_finish(hal_replay_ecu_t *run);

/*
 * One line of text, newline-terminated, on what the run read and did:
 *   "replay: lines L frames F not_classic S bad B first_bad_line N
 *    time_backwards T gaps_skipped G ticks K sent X own_fuel_ul A
 *    platoon_fuel_ul P rx_dropped D tx_dropped E\n"
 * (one line). Writes at most cap bytes with the NUL; returns the length.
 */
uint32_t hal_replay_ecu_summary(const hal_replay_ecu_t *run, char *buf, uint32_t cap);

#endif /* HAL_REPLAY_ECU_H */
