/*
 * The paper's quadrotor commanded to a point 1 m above it, called from C;
 * then every float input of both laws poisoned with NaN and with infinity,
 * one at a time, each of which must return a status and leave the output
 * as it was. Exits 0 when every check holds.
 *
 *   cc -std=c11 -Wall -Wextra -Wpedantic -Werror -I capi/include capi/examples/c/hover.c \
 *      target/debug/examples/libgeopid_control.a -lm -lpthread -ldl -o hover && ./hover
 */
#include "geopid_control.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

static int failures = 0;

static void check(int ok, const char *what) {
  if (!ok) {
    printf("FAIL: %s\n", what);
    failures++;
  }
}

static const float IDENTITY[3][3] = GPC_IDENTITY;

/* Poisons each float of `obj` in turn and checks the call refuses it. */
#define POISON_EACH(obj, call, label)                                           \
  do {                                                                          \
    float *fields = (float *)&(obj);                                            \
    size_t n = sizeof(obj) / sizeof(float);                                     \
    for (size_t k = 0; k < n; k++) {                                            \
      const float bad[2] = {NAN, INFINITY};                                     \
      for (int b = 0; b < 2; b++) {                                             \
        float saved = fields[k];                                                \
        fields[k] = bad[b];                                                     \
        memset(&sentinel, 0x5a, sizeof sentinel);                               \
        GpcStatus status = (call);                                              \
        fields[k] = saved;                                                      \
        char what[96];                                                          \
        snprintf(what, sizeof what, "%s float %zu = %s refused", label, k,      \
                 b ? "inf" : "nan");                                            \
        check(status != GPC_STATUS_OK, what);                                   \
        check(memcmp(&sentinel, &untouched, sizeof sentinel) == 0,              \
              "output untouched on error");                                     \
        checked++;                                                              \
      }                                                                         \
    }                                                                           \
  } while (0)

int main(void) {
  GpcVehicle vehicle = gpc_paper_vehicle();
  GpcPositionGains pos = gpc_paper_position_gains();
  GpcAttitudeGains att = gpc_paper_attitude_gains();
  GpcState state;
  memset(&state, 0, sizeof state);
  memcpy(state.r, IDENTITY, sizeof IDENTITY);
  GpcIntegrals integrals;
  memset(&integrals, 0, sizeof integrals);
  GpcPositionReference ref;
  memset(&ref, 0, sizeof ref);
  ref.x[2] = -1.0f; /* 1 m up: e3 points down */
  ref.b1d[0] = 1.0f;

  GpcPositionOutput out;
  GpcStatus status =
      gpc_position_update(&vehicle, &pos, &att, &state, &integrals, &ref, &out);
  printf("position update: %s, thrust %.4f N, moment (%.3g, %.3g, %.3g) N m\n",
         gpc_status_name(status), out.thrust, out.moment[0], out.moment[1],
         out.moment[2]);
  check(status == GPC_STATUS_OK, "hover command succeeds");
  /* A climb: more than the weight, straight along -b3, no moment. */
  check(out.thrust > vehicle.mass * vehicle.gravity, "thrust exceeds weight");
  check(fabsf(out.moment[0]) + fabsf(out.moment[1]) + fabsf(out.moment[2]) <
            1e-6f,
        "no moment when R = R_c");

  int checked = 0;
  GpcPositionOutput sentinel, untouched;
  memset(&untouched, 0x5a, sizeof untouched);
  POISON_EACH(vehicle, gpc_position_update(&vehicle, &pos, &att, &state,
                                           &integrals, &ref, &sentinel),
              "vehicle");
  POISON_EACH(state, gpc_position_update(&vehicle, &pos, &att, &state,
                                         &integrals, &ref, &sentinel),
              "state");
  POISON_EACH(integrals, gpc_position_update(&vehicle, &pos, &att, &state,
                                             &integrals, &ref, &sentinel),
              "integrals");
  POISON_EACH(ref, gpc_position_update(&vehicle, &pos, &att, &state,
                                       &integrals, &ref, &sentinel),
              "position reference");
  POISON_EACH(att, gpc_position_update(&vehicle, &pos, &att, &state,
                                       &integrals, &ref, &sentinel),
              "attitude gains");
  /* The position gains end with a byte flag: poison the floats before it. */
  {
    float *fields = (float *)&pos;
    size_t n = offsetof(GpcPositionGains, clamp_integral) / sizeof(float);
    for (size_t k = 0; k < n; k++) {
      float saved = fields[k];
      fields[k] = NAN;
      memset(&sentinel, 0x5a, sizeof sentinel);
      status = gpc_position_update(&vehicle, &pos, &att, &state, &integrals,
                                   &ref, &sentinel);
      fields[k] = saved;
      check(status == GPC_STATUS_INVALID_GAINS, "NaN position gain refused");
      check(memcmp(&sentinel, &untouched, sizeof sentinel) == 0,
            "output untouched on error");
      checked++;
    }
  }
  check(gpc_position_update(&vehicle, &pos, &att, &state, &integrals, &ref,
                            NULL) == GPC_STATUS_NULL_POINTER,
        "NULL output refused");

  /* The attitude law against a reference rolled by 0.1 rad. */
  GpcAttitudeReference aref;
  memset(&aref, 0, sizeof aref);
  memcpy(aref.rd, IDENTITY, sizeof IDENTITY);
  aref.rd[1][1] = cosf(0.1f);
  aref.rd[1][2] = -sinf(0.1f);
  aref.rd[2][1] = sinf(0.1f);
  aref.rd[2][2] = cosf(0.1f);
  GpcAttitudeOutput aout;
  status = gpc_attitude_update(&vehicle, &att, &state, &integrals, &aref, &aout);
  printf("attitude update: %s, moment (%.4g, %.4g, %.4g) N m, psi %.3g\n",
         gpc_status_name(status), aout.moment[0], aout.moment[1],
         aout.moment[2], aout.psi);
  check(status == GPC_STATUS_OK, "attitude command succeeds");
  check(aout.moment[0] > 0.0f, "rolls toward R_d (positive roll moment)");
  {
    GpcAttitudeOutput asentinel, auntouched;
    memset(&auntouched, 0x5a, sizeof auntouched);
    float *fields = (float *)&aref;
    for (size_t k = 0; k < sizeof aref / sizeof(float); k++) {
      float saved = fields[k];
      fields[k] = NAN;
      memset(&asentinel, 0x5a, sizeof asentinel);
      status = gpc_attitude_update(&vehicle, &att, &state, &integrals, &aref,
                                   &asentinel);
      fields[k] = saved;
      check(status != GPC_STATUS_OK, "NaN attitude reference refused");
      check(memcmp(&asentinel, &auntouched, sizeof asentinel) == 0,
            "output untouched on error");
      checked++;
    }
  }
  /* A transposed-and-scaled matrix is not a rotation. */
  state.r[0][0] = 2.0f;
  check(gpc_position_update(&vehicle, &pos, &att, &state, &integrals, &ref,
                            &out) == GPC_STATUS_NOT_A_ROTATION,
        "non-rotation refused");
  check(gpc_integrals_step(&integrals, NULL, NULL, NAN) ==
            GPC_STATUS_INVALID_PERIOD,
        "NaN period refused");
  /* A sampled loop's bookkeeping, as firmware writes it: arrays decay to
   * the pointers taken. */
  check(gpc_integrals_step(&integrals, aout.e_i_rate, NULL, 0.5f) ==
                GPC_STATUS_OK &&
            integrals.e_i_att[0] == 0.5f * aout.e_i_rate[0] &&
            integrals.e_i_pos[0] == 0.0f,
        "integrals advance by dt times their rate");
  float moment_up[3];
  check(gpc_vector_from_z_up(aout.moment, moment_up) == GPC_STATUS_OK &&
            moment_up[0] == aout.moment[0] &&
            moment_up[2] == -aout.moment[2],
        "a moment back to z-up keeps x and flips z");

  printf("%d poisoned inputs refused; %d failures\n", checked, failures);
  return failures == 0 ? 0 : 1;
}
