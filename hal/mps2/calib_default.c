/* calib_default.c - the replay image without a truck calibration: the
 * default calibration of hal_ecu_loop_config() (hal/mps2/image_calib.h). */
#include "hal/mps2/image_calib.h"

void image_calib_apply(pfe_ecu_config_t *cfg)
{
    (void)cfg;
}
