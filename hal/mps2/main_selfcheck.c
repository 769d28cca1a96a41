/*
 * main_selfcheck.c - the mps2-an386 image: known-answer run of the model.
 *
 * Runs pfe_selfcheck over the bundled hilly road (compiled in from
 * sim_host/data/roads/hilly.csv) for 1 and 5 trucks and prints the results
 * through semihosting, in exactly the format of the host tool
 * sim_host/tools/selfcheck.c, so that the two outputs can be compared byte for
 * byte. Exit status 0, or 1 if a run fails.
 */
#include <stdint.h>

#include "firmware/pfe_fixed.h"
#include "firmware/pfe_selfcheck.h"
#include "hal/mps2/semihost.h"

extern const int32_t road_hilly_grade_ppm[];
extern const uint32_t road_hilly_n_samples;
extern const uint32_t road_hilly_spacing_mm;

static void line_u64(const char *name, uint64_t value)
{
    hal_mps2_write_str("selfcheck:   ");
    hal_mps2_write_str(name);
    hal_mps2_write_str(" ");
    hal_mps2_write_u64(value);
    hal_mps2_write_str("\n");
}

int main(void)
{
    const pfe_road_t road = {road_hilly_grade_ppm, road_hilly_n_samples, road_hilly_spacing_mm};
    static const uint32_t sizes[2] = {1U, 5U};
    int status = 0;
    for (uint32_t k = 0U; k < 2U; k++) {
        pfe_selfcheck_result_t r;
        const int rc = pfe_selfcheck_run(&road, sizes[k], 25000, &r);
        hal_mps2_write_str("selfcheck: road hilly vehicles ");
        hal_mps2_write_u32(sizes[k]);
        hal_mps2_write_str(" set_speed_mm_s 25000\n");
        if (rc != PFE_OK) {
            hal_mps2_write_str("selfcheck:   error ");
            hal_mps2_write_i32(rc);
            hal_mps2_write_str("\n");
            status = 1;
            continue;
        }
        hal_mps2_write_str("selfcheck:   digest ");
        hal_mps2_write_hex64(r.digest);
        hal_mps2_write_str("\n");
        line_u64("steps", r.steps);
        line_u64("ticks", r.ticks);
        line_u64("sim_fuel_nl", r.sim_fuel_nl);
        line_u64("sim_time_q16", r.sim_time_q16);
        line_u64("sim_min_speed_mm_s", (uint64_t)r.sim_min_speed_mm_s);
        line_u64("sim_max_speed_mm_s", (uint64_t)r.sim_max_speed_mm_s);
        line_u64("est_fuel_ul", r.est_fuel_ul);
        line_u64("est_pos0_fuel_ul", r.est_pos0_fuel_ul);
    }
    return status;
}
