/*
 * A sketch of an out-of-tree controller for the Crazyflie firmware that
 * flies the paper's position mode through this library. Not built here: it
 * needs the firmware's headers (controller.h, stabilizer_types.h,
 * physicalConstants.h) and is written from the firmware's documented
 * out-of-tree controller interface. Check the struct fields against the
 * firmware version you build with.
 *
 * Build: link target/thumbv7em-none-eabihf/release/examples/libgeopid_control.a
 * (cargo build -p geopid-control --release --example geopid_control
 *  --target thumbv7em-none-eabihf --no-default-features --features libm)
 * into the app, with CONFIG_CONTROLLER_OOT=y.
 *
 * Frames: the Crazyflie's world and body frames are z-up (x forward,
 * y left); the laws' are z-down. The *_from_z_up calls convert the state
 * and the setpoint; the moment comes back through the same map (it is its
 * own inverse); the thrust is a magnitude and needs none.
 */
#include <math.h>
#include <string.h>

#include "controller.h"
#include "geopid_control.h"
#include "physicalConstants.h"
#include "stabilizer_types.h"

#define GPC_RATE RATE_500_HZ

static GpcVehicle vehicle;
static GpcPositionGains position_gains;
static GpcAttitudeGains attitude_gains;
static GpcIntegrals integrals;
static GpcStatus last_status;

void controllerOutOfTreeInit(void) {
  /* The Crazyflie 2.1: 27 g (37 g with a deck), J from its system
   * identification; retune the gains for it (the paper's are for 0.755 kg). */
  memset(&vehicle, 0, sizeof vehicle);
  vehicle.mass = CF_MASS;
  vehicle.inertia[0][0] = 16.571710e-6f;
  vehicle.inertia[1][1] = 16.655602e-6f;
  vehicle.inertia[2][2] = 29.261652e-6f;
  vehicle.gravity = GRAVITY_MAGNITUDE;
  position_gains = gpc_paper_position_gains();
  attitude_gains = gpc_paper_attitude_gains();
  memset(&integrals, 0, sizeof integrals);
}

bool controllerOutOfTreeTest(void) { return true; }

/* Body-to-world rotation of a unit quaternion (x, y, z, w), row-major. */
static void rotation_of(const quaternion_t *q, float r[3][3]) {
  const float x = q->x, y = q->y, z = q->z, w = q->w;
  r[0][0] = 1 - 2 * (y * y + z * z);
  r[0][1] = 2 * (x * y - w * z);
  r[0][2] = 2 * (x * z + w * y);
  r[1][0] = 2 * (x * y + w * z);
  r[1][1] = 1 - 2 * (x * x + z * z);
  r[1][2] = 2 * (y * z - w * x);
  r[2][0] = 2 * (x * z - w * y);
  r[2][1] = 2 * (y * z + w * x);
  r[2][2] = 1 - 2 * (x * x + y * y);
}

void controllerOutOfTree(control_t *control, const setpoint_t *setpoint,
                         const sensorData_t *sensors, const state_t *state,
                         const stabilizerStep_t tick) {
  if (!RATE_DO_EXECUTE(GPC_RATE, tick)) {
    return;
  }
  const float deg = (float)M_PI / 180.0f;
  GpcState up = {
      .x = {state->position.x, state->position.y, state->position.z},
      .v = {state->velocity.x, state->velocity.y, state->velocity.z},
      .omega = {sensors->gyro.x * deg, sensors->gyro.y * deg, sensors->gyro.z * deg},
  };
  rotation_of(&state->attitudeQuaternion, up.r);

  const float yaw = setpoint->attitude.yaw * deg;
  GpcPositionReference target_up = {
      .x = {setpoint->position.x, setpoint->position.y, setpoint->position.z},
      .v = {setpoint->velocity.x, setpoint->velocity.y, setpoint->velocity.z},
      .a = {setpoint->acceleration.x, setpoint->acceleration.y, setpoint->acceleration.z},
      .b1d = {cosf(yaw), sinf(yaw), 0.0f},
  };

  GpcState s;
  GpcPositionReference target;
  GpcPositionOutput out;
  gpc_state_from_z_up(&up, &s);
  gpc_position_reference_from_z_up(&target_up, &target);
  last_status = gpc_position_update(&vehicle, &position_gains, &attitude_gains,
                                    &s, &integrals, &target, &out);
  control->controlMode = controlModeForceTorque;
  if (last_status != GPC_STATUS_OK || setpoint->mode.z == modeDisable) {
    /* Bad input (a NaN from the estimator, say): motors off, integrals
     * kept; the status is there for a log variable. */
    control->thrustSi = 0.0f;
    control->torqueX = control->torqueY = control->torqueZ = 0.0f;
    return;
  }
  gpc_integrals_step(&integrals, out.e_i_att_rate, out.e_i_pos_rate,
                     1.0f / GPC_RATE);
  float moment_up[3];
  gpc_vector_from_z_up(out.moment, moment_up);
  control->thrustSi = out.thrust;
  control->torqueX = moment_up[0];
  control->torqueY = moment_up[1];
  control->torqueZ = moment_up[2];
}
