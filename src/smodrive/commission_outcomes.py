"""What each commissioning test's outcome is called, and what it means for
a user (smd_ident_outcome, core/include/smodrive/smd_ident.h): the names
smodrive.commission gives its results, the words `smodrive identify`
prints beside them (a step's own words where a name is shared:
``<name>_ls``, ``<name>_mech``)."""

from __future__ import annotations

#: the test's outcomes (smd_ident_outcome)
OUTCOMES = {0: "ok", 1: "running", 2: "no_current", 3: "overcurrent", 4: "not_settled",
            5: "poor_fit", 6: "bad_input", 7: "slipped", 8: "voltage_limit", 9: "sensor_range"}
#: what each outcome means, for a user
OUTCOME_TEXT = {
    "ok": "the fit is good (R^2 >= 0.999)",
    "running": "the test did not end within its time",
    "no_current": "the current never reached i_test below the voltage limit: no motor, "
                  "an open phase, or R_s too high for the test current",
    "overcurrent": "a phase current went beyond 1.5 i_test: the test stopped",
    "not_settled": "a level's current did not settle within t_level_max",
    "poor_fit": "the levels are not on a line (R^2 < 0.999): the values are not to be trusted",
    "bad_input": "a measured current or the DC-link voltage was not finite",
    "no_sensorless_range": "the sensorless drive hands over from its forced start where the "
                           "back EMF clears the inverter's drop (docs/design_from_motor.md, "
                           "w_M_if_enter), and for this motor and inverter that is too close to "
                           "rated speed: no room for the J and B test's ramp; a shorter dead "
                           "time or a motor with more EMF at rated speed",
    "slipped": "the rotor did not follow the spin (coasting, it turned at under half the "
               "frame's speed): a load heavier than the ramp allows, or a rotor that does not "
               "turn; a heavy load needs a slower sequence (commission(slow=...), identify "
               "--slow)",
    "sensor_range": "the measured current stopped following the voltage (it rose by under 1 % "
                    "of i_test while the voltage rose by what half of i_test takes): the current "
                    "sensors' range is reached or their signal lost, and a clipped sensor hides "
                    "the overcurrent check: the test stopped; check adc.full_scale against i_test",
    "levels_disagree": "the inductances measured at the three bias levels scatter beyond L's "
                       "stated accuracy (twice their weighted mean's standard error over 5 %): "
                       "the ADC's noise against the test's swing (a larger "
                       "--i-test, or adc.n_oversample), or a stator whose inductance moves with "
                       "its current; the value is not to be trusted",
    "poor_fit_ls": "the square wave's response does not fit the stator's discrete model: the "
                   "value is not to be trusted",
    "poor_fit_mech": "the speed ramp's and the coast's friction disagree by more than a twentieth "
                     "of the ramp's torque: the torque the drive reports is not the rotor's (a "
                     "sensorless angle that lags the rotor), or a load on the shaft; J and B are "
                     "not to be trusted",
    "voltage_limit_mech": "the DC link leaves step 4 no room: its speeds (a ramp of a fifth of "
                          "rated speed at least, above the handover) need more back EMF than "
                          "0.8 of inverter.u_dc / sqrt 3; check inverter.u_dc and motor.w_M_N",
    "fault_mech": "the drive designed from steps 1-3 (its R_s, L_s, psi_r and the guessed "
                  "inertia of step 3's spin) stopped in this fault while it ran step 4; a "
                  "step-3 inertia far from the rotor's is the usual cause: --slow 10 runs the "
                  "spin that measures it slower",
    "voltage_limit": "the spin's voltage reached the inverter's limit: the back EMF at half "
                     "rated speed is beyond the DC link's reach (a slower spin would not "
                     "help): check inverter.u_dc and motor.w_M_N",
}


#: smd_ident_mech_state.outcome
MECH_OUTCOMES = {0: "ok", 1: "running", 4: "not_settled", 5: "poor_fit", 6: "bad_input",
                 7: "fault"}
