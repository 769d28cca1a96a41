/*
 * The firmware codec and ECU, built over the tables dbc2c wrote from one
 * DBC, print what a DBC change must move (tests/codec_gen/codec_gen_test.sh):
 *
 *   lfe1_data        LFE1 as the codec encodes a fuel rate of 10 mL/s (36 L/h)
 *   speed_mm_s       CCVS1's speed decoded from raw 0x1000
 *   speed_unit       the unit of CCVS1 WheelBasedVehicleSpeed in the table
 *   status_frames    PFE_Status frames the ECU sends in 10 s once claimed
 *   status_cycle_ms  PFE_Status's period in the table
 *   status_pgn       PFE_PGN_STATUS, as the generated header says
 *   status_pgn_frames
 *                    frames sent in those 10 s with PGN 65284 and with 65290
 *   preview_ppm      a 3-sample preview whose samples all have raw 33000
 *                    (0x80E8), read back with pfe_preview_grade_ppm()
 *   preview_copy_ppm the same read with pfe_preview_copy_ppm()
 *   cvw_second_sender_after_4s
 *                    the CVW mass input, after a valid mass from sender 0x10
 *                    at 1 s: whether one from sender 0x20 at 5 s is taken
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
#include "pfe_input.h"

#include "../unit/ecu_harness.h" /* the ECU tests' module: config(), g_ecu */

/* Frames of PGN 65284 and 65290 among those counted by status_frames(). */
static uint32_t g_pgn_65284;
static uint32_t g_pgn_65290;

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
            const uint32_t pgn = pfe_j1939_pgn(g_tx[i].id);
            *frames += (pgn == PFE_PGN_STATUS) ? 1U : 0U;
            g_pgn_65284 += (pgn == 65284U) ? 1U : 0U;
            g_pgn_65290 += (pgn == 65290U) ? 1U : 0U;
        }
    }
    return 0;
}

/* A preview of three samples, each raw 33000, through the reassembly. */
static int preview(void)
{
    static pfe_preview_t pv;
    pfe_preview_init(&pv);
    pfe_msg_grade_preview_t m;
    (void)memset(&m, 0, sizeof m);
    m.frame_type = (pfe_sig_u32_t){PFE_PREVIEW_FRAME_HEADER, PFE_SIG_VALID};
    m.preview_id = (pfe_sig_u32_t){5U, PFE_SIG_VALID};
    m.sample_count = (pfe_sig_u32_t){3U, PFE_SIG_VALID};
    m.spacing_m = (pfe_sig_u32_t){10U, PFE_SIG_VALID};
    pfe_can_frame_t f;
    if ((pfe_codec_encode_grade_preview(&f, &m, 0x27U) < 0) || (pfe_preview_push(&pv, &f) < 0)) {
        return -1;
    }
    m.frame_type = (pfe_sig_u32_t){PFE_PREVIEW_FRAME_DATA, PFE_SIG_VALID};
    m.first_index = (pfe_sig_u32_t){0U, PFE_SIG_VALID};
    for (uint32_t k = 0U; k < PFE_PREVIEW_SAMPLES_PER_FRAME; k++) {
        m.grade_ppm[k] = (pfe_sig_i32_t){0, PFE_SIG_VALID};
    }
    if (pfe_codec_encode_grade_preview(&f, &m, 0x27U) < 0) {
        return -1;
    }
    for (uint32_t b = 2U; b < 8U; b += 2U) { /* GradeSample0..2 at bits 16, 32, 48 */
        f.data[b] = 0xE8U;
        f.data[b + 1U] = 0x80U;
    }
    if (pfe_preview_push(&pv, &f) != PFE_PREVIEW_COMPLETE) {
        return -1;
    }
    printf("preview_ppm");
    for (uint32_t k = 0U; k < 3U; k++) {
        int32_t ppm;
        if (pfe_preview_grade_ppm(&pv, k, &ppm) != PFE_SIG_VALID) {
            return -1;
        }
        printf(" %" PRId32, ppm);
    }
    int32_t copy[3];
    if (pfe_preview_copy_ppm(&pv, 0U, 3U, copy) != 3U) {
        return -1;
    }
    printf("\npreview_copy_ppm %" PRId32 " %" PRId32 " %" PRId32 "\n", copy[0], copy[1], copy[2]);
    return 0;
}

/* Whether a second CVW sender is taken 4 s after the first one's last mass. */
static void cvw_second_sender(void)
{
    pfe_input_t in;
    pfe_input_init(&in, PFE_IN_MASS, PFE_INPUT_NO_SOURCE);
    const pfe_input_verdict_t first = pfe_input_take(&in, 0x10U, PFE_SIG_VALID, 40000, 1000000U);
    const pfe_input_verdict_t second = pfe_input_take(&in, 0x20U, PFE_SIG_VALID, 30000, 5000000U);
    printf("cvw_second_sender_after_4s %s\n",
           (first != PFE_INPUT_ACCEPTED) ? "first-refused"
           : (second == PFE_INPUT_ACCEPTED) ? "taken"
           : (second == PFE_INPUT_IGNORED)  ? "ignored"
                                            : "other");
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
    printf("status_pgn %lu\n", (unsigned long)PFE_PGN_STATUS);
    printf("status_pgn_frames 65284:%" PRIu32 " 65290:%" PRIu32 "\n", g_pgn_65284, g_pgn_65290);
    if (preview() != 0) {
        return 1;
    }
    cvw_second_sender();
    return 0;
}
