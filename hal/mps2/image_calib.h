/*
 * image_calib.h - the truck calibration compiled into a Cortex-M4 replay
 * image (hal/mps2/main_ecu.c), which reads no calibration file: the image
 * for a given truck links a file that sim_host/tools/cal2c.c generated from that
 * truck's calibration file (sim_host/lib/truck_cal.h), the default image
 * hal/mps2/calib_default.c. The host's pfe_ecu_replay --calib FILE and the
 * image built from FILE run the same configuration.
 */
#ifndef IMAGE_CALIB_H
#define IMAGE_CALIB_H

#include "firmware/pfe_ecu.h"

/* Points cfg's own_vehicle and vehicle_at[] at the compiled-in
 * calibrations and sets the module options, as truck_cal_apply() does on
 * the host; the default image leaves cfg as it is. Cannot fail. */
void image_calib_apply(pfe_ecu_config_t *cfg);

#endif /* IMAGE_CALIB_H */
