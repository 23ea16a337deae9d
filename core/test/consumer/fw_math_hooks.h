/* The math hooks of smd_types.h as a firmware would map them (to CMSIS-DSP,
 * a CORDIC unit, tables): declarations only. package_check.cmake (MODE=cross)
 * compiles the core with
 *   -DSMD_MATH_HEADER="fw_math_hooks.h" -DSMD_SINF=fw_sinf ... -DSMD_FLOORF=fw_floorf
 * and checks that the objects call these and no float libm function. */
#ifndef FW_MATH_HOOKS_H
#define FW_MATH_HOOKS_H

#ifdef __cplusplus
extern "C" {
#endif

float fw_sinf(float x);
float fw_cosf(float x);
float fw_sqrtf(float x);
float fw_atan2f(float y, float x);
float fw_fabsf(float x);
float fw_expf(float x);
float fw_expm1f(float x);
float fw_floorf(float x);

#ifdef __cplusplus
}
#endif

#endif
