"""The registry's scenes, not imported: name -> (family module, description).

Generated from the registry (:mod:`assemblies.scenes`) by
``python -m assemblies.scenes.listing --index``; a test holds it to the registry, so the
two cannot drift. The scenes import the components, their references scipy and their
plots matplotlib: the command line checks and lists a scene, and
:func:`assemblies.scenes.scene` finds the one family module to import, from this file alone.
"""

SCENE_INDEX = {
    'stick_slip': ('friction',
        'seed 9.2: block pulled through a spring at constant speed, stick-slip'),
    'friction_damping': ('friction',
        'seed 9.4: free vibration with dry friction, amplitudes fall linearly'),
    'axle_pendulum': ('axle',
        'seed 8.5: disk on an inclined axle through its rim, released from rest'),
    'coin_rolling': ('coin',
        'seed ch. 6: a coin rolling without slip from a given state'),
    'coin_upright': ('coin',
        'seed ch. 6: straight upright rolling at 1.1 x the critical speed'),
    'coin_circle': ('coin',
        'seed ch. 6: steady circular rolling at a 30 degree lean'),
    'torque_free_flip': ('coin',
        'seed 8.3: spin about the intermediate axis turns the body over'),
    'skate': ('coin',
        'seed 5.5: skate with a knife edge on ice, its heading settles'),
    'beam_free_vibration': ('beam',
        'seed 7.5: cantilever released from its static shape under a tip load, undamped'),
    'beam_tip_force': ('beam',
        'seed 7.5: damped cantilever settling under a constant tip force'),
    'moving_table': ('table',
        'seed 9.6 ex. 1: block sliding on a table shaken as U sin(wt)'),
    'still_table': ('table',
        'seed 9.6 ex. 1 without the shaking: the same block on a still table slows '
        'linearly and stops (the reference case moving_table is measured against)'),
    'conveyor': ('table',
        'seed 9.6 ex. 2: asymmetric shaking conveys the block at a steady speed'),
    'two_block_belt': ('joined',
        'two blocks on a moving belt, springs to the walls and between them, Coulomb '
        'friction: stick, slip, re-stick, then steady sliding'),
    'axle_motor': ('joined',
        "seed 8.5's disk with Coulomb bearing friction, lifted by a DC motor through a "
        'torsional spring until it stalls'),
    'beam_friction_damper': ('joined',
        'cantilever released from a tip deflection, its tip rubbing on a spring-loaded '
        'friction pad (Jenkins element) until the pad sticks for good'),
    'speed_control': ('speed_control',
        'a foreign PI controller FMU (CasADi export, FMI 3 ME) holds a block sliding on a'
        ' rough floor at 1 m/s'),
    'steady_sliding': ('friction_seed',
        'seed 9.2: steady sliding x = v t - mu_k m g/k; a disturbance keeps its amplitude'
        ' without damping and dies out at d/2m with it (exact Coulomb friction)'),
    'stick_slip_damped': ('friction_seed',
        'seed 9.2: stick-slip survives a little damping in the spring (d = 0.05), not a '
        'lot (d = 0.5 slides steadily after one slip); exact Coulomb friction'),
    'stick_slip_smooth': ('friction_seed',
        'seed 9.2, Fig. 9.4: the smooth friction law Eq. 9.5 (eps = 1e-3, and 1e-4) '
        "against the exact stick-slip's t1 and t2"),
    'resonance_eq_9_10': ('friction_seed',
        'seed 9.5, Figs. 9.6 and 9.7 as the seed computes them: Eq. 9.10, mu '
        "tanh(x'/0.001) (SpringBlock's tanh law with eps = 0.003), U = 0.4 and U = 1 from"
        ' x(0) = 10'),
    'distinguished_limit': ('friction_seed',
        'seed 9.3: the block as two halves m/2 joined by a stiff spring K = 1e2, 1e3, 1e4'
        ' N/m, pulled as in 9.2 (exact Coulomb friction): the front half slips at t1/2 = '
        "4 s, before the rigid block's 8 s, whatever K"),
    'limits_order': ('friction_seed',
        'seed 9.3, the other order of the limits: K -> oo first (the rigid block under '
        'Eq. 9.5, eps = 1e-3 and 1e-4) slips at ~8 s, eps -> 0 first (two halves, exact '
        'Coulomb, K = 1e4 N/m) at 4 s'),
    'distinguished_limit_n4': ('friction_seed',
        'seed 9.3: the block as n = 4 masses m/4 joined by stiff springs K = 1e2, 1e3, '
        '1e4 N/m (exact Coulomb friction): the front mass slips earlier still, at t1/4 = '
        '2 s, whatever K'),
    'resonance_growth': ('friction_seed',
        'seed 9.5, Fig. 9.7: spring end moved as U sin t, U = 1, mu = 0.6, x(0) = 10; '
        "exact Coulomb friction (the seed's figure uses Eq. 9.10, mu tanh(v/0.001), "
        "without Eq. 9.7's factor 3): |x| grows at (U pi - 4 mu)/(2 pi) = 0.118"),
    'resonance_below': ('friction_seed',
        "seed 9.5, Fig. 9.6: U = 0.4 < 4 mu / pi, exact Coulomb friction (the seed's "
        'figure uses Eq. 9.10, mu tanh(v/0.001)): from x(0) = 10 no resonant growth; from'
        ' x(0) = -10, in phase, |x| falls at (U pi - 4 mu)/(2 pi) = -0.182'),
    'cylinder_incline': ('bodies_seed',
        'seed 8.1: a uniform cylinder rolls without slip down a 30 degree incline'),
    'shell_rolling': ('bodies_seed',
        'seed 8.2: a hemispherical shell rocks on a table without slip'),
    'shell_frictionless': ('bodies_seed',
        'seed 8.2: a hemispherical shell rocks on a frictionless table'),
    'rod_on_rollers': ('bodies_seed',
        'seed 9.6 ex. 3: a rod on two counter-rotating rollers oscillates'),
    'wobbling_disk': ('bodies_seed',
        'seed 8.4: a thrown disk wobbles at twice its spin rate'),
    'thrown_disk': ('bodies_seed',
        'seed 8.3.2: a disk thrown with an imperfect spin, its axis cones about H'),
    'nutation_damper': ('bodies_seed',
        'seed 8.3.1: spun about its minor axis, a body with a viscous damper inside ends '
        'spinning about its major axis'),
    'cone_incline': ('bodies_exercises',
        'seed 8.6 ex. 2: a uniform cone rolls without slip on an incline, rocking about '
        'its fixed apex'),
    'wobble_exercise': ('bodies_exercises',
        'seed 8.6 ex. 3: the disk from phi = 1.0, theta = 1.3, psi = -0.4 spun about its '
        'axis, nudged: it wobbles at twice its spin'),
    'axle_inertia': ('bodies_exercises',
        "seed 8.6 ex. 4: a body's inertia matrix recovered from its periods on six axles "
        '(section 8.5 turned round)'),
    'string_body': ('bodies_exercises',
        'seed 8.6 ex. 5: a box hung from a point on its surface by a damped elastic '
        'string: energy falls, not to zero; vertical H about the support kept'),
    'sliding_rod': ('sliding',
        'seed 9.8: a rod sliding and spinning on a table (Eqs. 9.14-9.16, uniform '
        'reaction) stops translating and rotating at the same instant'),
    'sliding_disk': ('sliding',
        'seed 9.8: a disk sliding and spinning on a table under a uniform pressure, its '
        'friction integrals by quadrature in the model, stops translating and rotating at'
        ' the same instant'),
    'sliding_disk_parabolic': ('sliding',
        'seed 9.8: the disk of sliding_disk under a parabolic pressure p ~ 1 - r^2/R^2: '
        'it too stops translating and rotating at once, its speed vanishing faster (the '
        'ratio tends to 0)'),
    'burridge_knopoff': ('burridge_knopoff',
        'issue 30: Burridge-Knopoff chain, C&L velocity-weakening friction, exact stick-'
        'slip'),
    'translational_oscillator': ('msl_translational',
        'MSL Translational.Examples.Oscillator: masses on springs driven at resonance, '
        'undamped and damped'),
    'translational_friction': ('msl_translational',
        'MSL Translational.Examples.Friction: Stribeck friction with stick/slip under a '
        'sine force, and a mass thrown against its hard stop'),
    'translational_brake': ('msl_translational',
        'MSL Translational.Examples.Brake: a sliding mass braked to rest by a normal '
        'force stepped on at 0.1 s'),
    'translational_elastogap': ('msl_translational',
        'MSL Translational.Examples.ElastoGap: a mass on spring-dampers beside one '
        'between ElastoGaps that lift off'),
    'translational_preload': ('msl_translational',
        'MSL Translational.Examples.PreLoad: a spool held by two preloaded ElastoGap '
        'stops until a slow sine force overcomes the preload'),
    'coupled_clutches': ('msl_rotational',
        'MSL Rotational.Examples.CoupledClutches: four inertias, three clutches engaging '
        'and releasing in turn (exact lock/break-away events)'),
    'rotational_friction': ('msl_rotational_friction',
        'MSL Rotational.Examples.Friction: a driven inertia, a clutch, a spring-damper '
        'and a brake engaged at 0.5 s (exact stick/slip events)'),
    'rotational_one_way_clutch': ('msl_rotational_friction',
        'MSL Rotational.Examples.OneWayClutch: a one-way clutch engaged by a pulse '
        'between two inertias (exact lock/overrun events, freewheel)'),
    'rotational_first': ('msl_rotational_examples',
        'MSL Rotational.Examples.First: a sine torque drives a motor through a gear, a '
        'damped bearing and a spring into a load'),
    'rotational_backlash': ('msl_rotational_examples',
        'MSL Rotational.Examples.Backlash: inertias released on a spring-damper, an '
        'ElastoBacklash and an ElastoBacklash2'),
}
SCENE_NAMES = tuple(SCENE_INDEX)
