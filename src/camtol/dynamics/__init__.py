"""Follower dynamics at speed, of the nominal and of the as-made cam (THEORY §9).

The follower train (:mod:`.train`), the lift that drives it (:mod:`.lift`: the design,
a cut cam, a scanned cam), its periodic steady state through the frequency domain
(:mod:`.steady`), the jump speed and the separations above it (:mod:`.jump`), the normal
contact force, camshaft torque and Hertz stress (:mod:`.stress`), one study from its
inputs (:mod:`.run`), Monte Carlo samples of the tolerances (:mod:`.montecarlo`) and the
return spring for a jump margin (:mod:`.spring`).
"""

from camtol.dynamics.jump import Separation, jump_speed_rpm, separations, simulate
from camtol.dynamics.lift import CamLift, cut_lift, nominal_lift, scan_lift
from camtol.dynamics.run import DynamicsInputs, DynamicsResult, run_dynamics
from camtol.dynamics.steady import SteadyState, residual_vibration, steady_state
from camtol.dynamics.stress import cam_contacts, hertz_stress_mpa
from camtol.dynamics.train import ContactMaterials, DynamicsTable, FollowerTrain, follower_train

__all__ = [
    "CamLift",
    "ContactMaterials",
    "DynamicsInputs",
    "DynamicsResult",
    "DynamicsTable",
    "FollowerTrain",
    "Separation",
    "SteadyState",
    "cam_contacts",
    "cut_lift",
    "follower_train",
    "hertz_stress_mpa",
    "jump_speed_rpm",
    "nominal_lift",
    "residual_vibration",
    "run_dynamics",
    "scan_lift",
    "separations",
    "simulate",
    "steady_state",
]
