/*
 * log_vectors.h - log lines both log readers must read alike: the host's
 * (sim_host/lib/log/log.h, every host tool) and the heap-free one of the replay
 * bus (hal/replay/hal_replay.h, the Cortex-M4 image). Included by
 * tests/host/test_canlog.c and tests/hal/test_hal_replay.c, each of which
 * reads every line on its own, as a one-line log, and checks:
 *
 *   LV_FRAME    a classic data frame: time (us), id (| 0x80000000 for 29
 *               bits), length and data (hex) exactly so;
 *   LV_SKIP     a valid line that is no classic data frame (remote, CAN FD,
 *               error frame): canlog returns it with its flags, the replay
 *               bus skips and counts it (skipped_not_classic);
 *   LV_COMMENT  no frame and no error: canlog counts a comment (and, alone
 *               in a file, reports it empty), the replay bus an empty line;
 *   LV_BAD      an error in both: canlog names a reason, the replay bus
 *               counts a bad line;
 *   LV_NO_TIME  candump's printed form without -t: canlog reads a frame at
 *               time 0 (for pfe_decode), the replay bus calls it bad (no
 *               time to replay it at), and so do the host's replays.
 *
 * Times: candump -t a/z/d print seconds and a fraction; -t A prints a date,
 * read as UTC (2026-12-01 10:00:00 UTC is 1796119200 s after 1970). A -t d
 * delta alone in a file is its own time.
 *
 * LOG_VECTOR(line, kind, time_us, id, len, data_hex)
 */
/* candump -L, as canplayer reads it */
LOG_VECTOR("(1700000000.010000) vcan0 18FEF100#0011223344556677", LV_FRAME, 1700000000010000ULL,
           0x98FEF100UL, 8U, "0011223344556677")
LOG_VECTOR("(1700000000.123456789) can0 0CF00400#FF", LV_FRAME, 1700000000123456ULL, 0x8CF00400UL,
           1U, "FF")
LOG_VECTOR("(1.000000) can0 123#de.ad", LV_FRAME, 1000000ULL, 0x123UL, 2U, "DEAD")
LOG_VECTOR("(1.000000) can0 7FF#", LV_FRAME, 1000000ULL, 0x7FFUL, 0U, "")
LOG_VECTOR("(1.000000) can0 123#11 R", LV_FRAME, 1000000ULL, 0x123UL, 1U, "11")
LOG_VECTOR("(1.000000)  vcan10  123#11\r", LV_FRAME, 1000000ULL, 0x123UL, 1U, "11")
LOG_VECTOR("(1.000000) can0 123#R", LV_SKIP, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(1.000000) can0 18FEF100#R8", LV_SKIP, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(1.000000) can0 123##1AABB", LV_SKIP, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(1.000000) can0 20000004#0004000000000000", LV_SKIP, 0ULL, 0UL, 0U, "")
/* candump's printed form: -t z (since the first frame), as benches record */
LOG_VECTOR("(000.011063)  can0  18FEF100   [8]  FF 12 34 56 78 9A BC DE", LV_FRAME, 11063ULL,
           0x98FEF100UL, 8U, "FF123456789ABCDE")
LOG_VECTOR("(012.500000)  can0  0CF00400   [8]  F0 FF 7D 20 1A FF FF FF", LV_FRAME, 12500000ULL,
           0x8CF00400UL, 8U, "F0FF7D201AFFFFFF")
/* -t a (seconds since 1970), -t d (a delta: alone, its own time) */
LOG_VECTOR("(1700000000.010000)  vcan0  18FEF100   [8]  00 11 22 33 44 55 66 77", LV_FRAME,
           1700000000010000ULL, 0x98FEF100UL, 8U, "0011223344556677")
LOG_VECTOR("(1700000000.123456789)  can0  123   [1]  01", LV_FRAME, 1700000000123456ULL, 0x123UL, 1U,
           "01")
LOG_VECTOR("(000.000000)  can0  123   [2]  0A 0B", LV_FRAME, 0ULL, 0x123UL, 2U, "0A0B")
/* -t A (a date, read as UTC) */
LOG_VECTOR("(2026-12-01 10:00:00.123456)  can0  18FEF100   [8]  FF 12 34 56 78 9A BC DE", LV_FRAME,
           1796119200123456ULL, 0x98FEF100UL, 8U, "FF123456789ABCDE")
/* -x's direction columns, -a's ASCII column, no data, a tab between fields */
LOG_VECTOR("(000.011063)  can0  RX - -  18FEF100   [8]  FF 12 34 56 78 9A BC DE", LV_FRAME, 11063ULL,
           0x98FEF100UL, 8U, "FF123456789ABCDE")
LOG_VECTOR("(000.011063)  can0  123   [2]  41 42   'AB'", LV_FRAME, 11063ULL, 0x123UL, 2U, "4142")
LOG_VECTOR("(000.100000)  can0  123   [0]", LV_FRAME, 100000ULL, 0x123UL, 0U, "")
LOG_VECTOR("(000.100000)\tcan0\t123\t[1]\t0a", LV_FRAME, 100000ULL, 0x123UL, 1U, "0A")
/* printed frames that are not classic data frames */
LOG_VECTOR("(000.100000)  can0  123   [4]  remote request", LV_SKIP, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(000.100000)  can0  123  [04]  remote request", LV_SKIP, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(000.100000)  can0  123  [12]  00 11 22 33 44 55 66 77 88 99 AA BB", LV_SKIP, 0ULL, 0UL,
           0U, "")
LOG_VECTOR("(000.100000)  can0  20000004   [8]  00 04 00 00 00 00 00 00   ERRORFRAME", LV_SKIP, 0ULL,
           0UL, 0U, "")
/* no frame, no error */
LOG_VECTOR("", LV_COMMENT, 0ULL, 0UL, 0U, "")
LOG_VECTOR("   ", LV_COMMENT, 0ULL, 0UL, 0U, "")
LOG_VECTOR("# recorded on the bench", LV_COMMENT, 0ULL, 0UL, 0U, "")
LOG_VECTOR("// a comment", LV_COMMENT, 0ULL, 0UL, 0U, "")
LOG_VECTOR("DROPCOUNT: dropped 3 CAN frames on 'can0' socket (total drops 3)", LV_COMMENT, 0ULL, 0UL,
           0U, "")
/* errors */
LOG_VECTOR("garbage", LV_BAD, 0ULL, 0UL, 0U, "")
LOG_VECTOR("\x01\x02\x03", LV_BAD, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(1.5) can0 123#11", LV_BAD, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(1.000000) can0 123#1G", LV_BAD, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(1.000000) can0 123#112", LV_BAD, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(1.000000) can0 123#112233445566778899", LV_BAD, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(1.000000) can0 800#11", LV_BAD, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(1.000000) can0 1234#11", LV_BAD, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(1.000000) can0 123#11 extra", LV_BAD, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(1.000000) can0", LV_BAD, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(000.011063)  can0  18FEF100   [9]  FF 12 34 56 78 9A BC DE 00", LV_BAD, 0ULL, 0UL, 0U,
           "")
LOG_VECTOR("(000.011063)  can0  123   [2]  0A", LV_BAD, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(000.011063)  can0  123   [1]  0A 0B", LV_BAD, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(000.011063)  can0  123   [1]  0G", LV_BAD, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(000.011063)  can0  12G   [1]  00", LV_BAD, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(000.011063)  can0  123   [1]  00 trailing", LV_BAD, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(000.0110)  can0  123   [1]  00", LV_BAD, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(2026-13-01 10:00:00.000000)  can0  123   [1]  0A", LV_BAD, 0ULL, 0UL, 0U, "")
LOG_VECTOR("(2026-12-01 24:00:00.000000)  can0  123   [1]  0A", LV_BAD, 0ULL, 0UL, 0U, "")
/* printed without -t */
LOG_VECTOR("can0  18FEF100   [8]  FF 12 34 56 78 9A BC DE", LV_NO_TIME, 0ULL, 0x98FEF100UL, 8U,
           "FF123456789ABCDE")
