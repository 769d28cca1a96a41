/*
 * The firmware codec and ECU, built over the tables dbc2c wrote from one
 * DBC, print what a DBC change must move (tests/codec_gen/codec_gen_test.sh):
 *
 *   lfe1_data        LFE1 as the codec encodes a fuel rate of 10 mL/s (36 L/h)
 *   speed_mm_s       CCVS1's speed decoded from raw 0x1000
 *   speed_unit       the unit of CCVS1 WheelBasedVehicleSpeed in the table
 *   status_frames    PFE_Status frames the ECU sends in 10 s once claimed
 *   status_cycle_ms  PFE_Status's period in the table
 *
 * One "key value" line each; exit status 1 if the codec or ECU refused a call.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <inttypes.h>
#include <stdio.h>
#include <string.h>

#include "pfe_calib.h"
#include "pfe_can.h"
#include "pfe_codec.h"
#include "pfe_ecu.h"

#include "../unit/ecu_harness.h" /* the ECU tests' module: config(), g_ecu */

static int status_frames(uint32_t *frames)
{
    const pfe_ecu_config_t c = config();
    uint64_t now_us = 1000000U;
    if (pfe_ecu_init(&g_ecu, &c, NULL, -1, now_us) != PFE_OK) {
        return -1;
    }
    *frames = 0U;
    /* 300 ms to claim the address (250 ms), then 1000 ticks: 10 s */
    for (uint32_t k = 0U; k < 1030U; k++) {
        g_ntx = pfe_ecu_tick(&g_ecu, now_us, g_tx, PFE_ECU_TX_MAX);
        now_us += PFE_ECU_TICK_US;
        for (uint32_t i = 0U; (i < g_ntx) && (k >= 30U); i++) {
            *frames += (pfe_j1939_pgn(g_tx[i].id) == PFE_PGN_STATUS) ? 1U : 0U;
        }
    }
    return 0;
}

int main(void)
{
    pfe_can_frame_t f;
    const pfe_msg_lfe1_t lfe1 = {{10000000U, PFE_SIG_VALID}};
    if (pfe_codec_encode_lfe1(&f, &lfe1, PFE_CODEC_DEFAULT_ADDRESS) < 0) {
        return 1;
    }
    printf("lfe1_data");
    for (uint32_t k = 0U; k < f.dlc; k++) {
        printf(" %02X", (unsigned)f.data[k]);
    }
    printf("\n");

    pfe_can_frame_t ccvs1 = {.id = PFE_CAN_EFF_FLAG | 0x18FEF100UL, .dlc = 8U,
                             .data = {0xFFU, 0x00U, 0x10U, 0xFFU, 0xFFU, 0xFFU, 0xFFU, 0xFFU}};
    pfe_msg_ccvs1_t speed;
    if ((pfe_codec_decode_ccvs1(&ccvs1, &speed) != PFE_OK) || (speed.speed_mm_s.state != PFE_SIG_VALID)) {
        return 1;
    }
    printf("speed_mm_s %" PRId32 "\n", speed.speed_mm_s.value);
    printf("speed_unit %s\n", pfe_codec_signals[PFE_CSIG_CCVS1_WHEEL_BASED_VEHICLE_SPEED].unit);

    uint32_t frames = 0U;
    if (status_frames(&frames) != 0) {
        return 1;
    }
    printf("status_frames %" PRIu32 "\n", frames);
    printf("status_cycle_ms %u\n", (unsigned)pfe_codec_messages[PFE_MSG_STATUS].cycle_ms);
    return 0;
}
