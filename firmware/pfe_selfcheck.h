/*
 * pfe_selfcheck.h - known-answer run of the whole model.
 *
 * Drives a platoon over a road with the object-model simulation and feeds
 * the estimator, every 10 ms, what the bus would carry on that drive (speed
 * quantised to SPN 84's 1/256 km/h and fresh every 100 ms, grade every
 * 10 ms). Every output of both is folded into a 64-bit FNV-1a digest. The
 * same road and platoon give the same digest on any target that computes
 * the model correctly: an image proves it by printing its digest next to a
 * host build's.
 *
 * Memory: static storage for one platoon and one estimator (about 2.7 KiB);
 * not reentrant. Cost: one simulation step per distance step plus one
 * estimator step per 10 ms of driving.
 */
#ifndef PFE_SELFCHECK_H
#define PFE_SELFCHECK_H

#include <stdint.h>

#include "pfe_sim.h"

typedef struct {
    uint64_t digest;            /* FNV-1a over every output */
    uint32_t steps;             /* simulation steps */
    uint32_t ticks;             /* estimator steps (10 ms) */
    uint64_t sim_fuel_nl;       /* object model over the road */
    uint64_t sim_time_q16;      /* s * 2^16 */
    int32_t sim_min_speed_mm_s;
    int32_t sim_max_speed_mm_s;
    uint64_t est_fuel_ul;       /* estimator, platoon */
    uint64_t est_pos0_fuel_ul;  /* estimator, lead vehicle */
} pfe_selfcheck_result_t;

/*
 * Runs n_vehicles default trucks (pfe_calib.h) 10 m apart at set speed
 * set_speed_mm_s over the road in 10 m steps. Returns PFE_OK, PFE_EINVAL
 * (bad arguments) or PFE_ESTALL.
 */
int pfe_selfcheck_run(const pfe_road_t *road, uint32_t n_vehicles, int32_t set_speed_mm_s,
                      pfe_selfcheck_result_t *out);

/* SPN 84 round trip in integers: mm/s to 1/256 km/h (rounded) and back to
 * mm/s (rounded), as a receiver decodes what a sender quantised. */
int32_t pfe_selfcheck_spn84_mm_s(int32_t speed_mm_s);

#endif /* PFE_SELFCHECK_H */
