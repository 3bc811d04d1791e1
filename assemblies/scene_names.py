"""The scene names in the registry's order, without importing the scenes.

The scenes import the components, and the components CasADi (seconds): the command line
checks and lists a scene name before it loads any of that. A test holds this list to the
registry (:data:`assemblies.scenes.SCENES`), so the two cannot drift.
"""
SCENE_NAMES = (
    "stick_slip", "friction_damping", "axle_pendulum", "coin_rolling", "coin_upright",
    "coin_circle", "torque_free_flip", "skate", "beam_free_vibration", "beam_tip_force",
    "moving_table", "conveyor", "two_block_belt", "axle_motor", "beam_friction_damper",
    "speed_control", "steady_sliding", "stick_slip_damped", "stick_slip_smooth",
    "distinguished_limit", "distinguished_limit_n4", "resonance_growth", "resonance_below",
    "cylinder_incline", "shell_rolling", "shell_frictionless", "rod_on_rollers",
    "wobbling_disk", "thrown_disk", "nutation_damper",
)
