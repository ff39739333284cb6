"""The one catalogue of controllers, keyed by (plant, controller): gains, units, defaults, bounds.

`chassistune list controllers --json`, `--gains`, `tune`, study configs and exported tables all
read it. The ABS PID and the suspension PID share a name, not their bounds. Every built-in entry
is listed below, explicitly; `register()` adds another under the same rules.

abs-wheel (design.md 4): the gains act on the slip error e = S_target - S; the pressure command
integrates through the actuator K/(s(Ts+1)).

quarter-car (design.md 3.4, 4): force u acts + on the body and - on the wheel; e = 0 - y. Gain units
are those of the default feedback y = body vertical velocity (then kp is a sky-hook damper, ki a sky
spring since int(vs) = zs, kd a sky inertance with the filter N s/(s + N)). The bounds span the
forces an active suspension actuator delivers: on an ISO class B road at 20 m/s the passive body
velocity, displacement and acceleration have RMS of about 0.05-0.07 m/s, 0.015 m and 0.6-1.7 m/s^2,
so the upper bounds give about 0.5-1.5 kN RMS there and 4x that on class D; every optimum we found
for either preset lies well inside. For other feedback signals the units change (see
docs/suspension.md); Jing and Xu 2023 (iabc-suspension) tuned all three gains on [0, 500]
(PAPER_BOX).
"""

from __future__ import annotations

from chassistune._registry import Registry
from chassistune.controllers.specs import ControllerSpec, GainSpec, ParamSpec

ABS_WHEEL = "abs-wheel"
QUARTER_CAR = "quarter-car"

_BY_PLANT: dict[str, Registry[ControllerSpec]] = {}


def register(spec: ControllerSpec) -> ControllerSpec:
    """Add a controller of `spec.plant`; registering the same (plant, name) twice is refused."""
    _BY_PLANT.setdefault(spec.plant, Registry("controller")).register(spec.name, spec)
    return spec


def get(plant: str, name: str) -> ControllerSpec:
    """The controller `name` of `plant`, or InputError listing the plant's controllers."""
    return _BY_PLANT.get(plant, Registry("controller")).get(name, f" for plant {plant!r}")


def for_plant(plant: str) -> list[ControllerSpec]:
    """All controllers of a plant, in catalogue order."""
    reg = _BY_PLANT.get(plant)
    return [reg.get(n) for n in reg.names()] if reg else []


# -- abs-wheel ---------------------------------------------------------------------------------

AMPLITUDE = ParamSpec(
    "amplitude",
    "-",
    None,
    "pressure command magnitude (rate K*amplitude); default reaches q_max in 0.15 s",
    positive=True,
)

SAMPLE_PERIOD = ParamSpec(
    "ts_s",
    "s",
    1e-3,
    "sample period of the switching law (rounded to whole integration steps, at least one)",
    positive=True,
)

register(
    ControllerSpec(
        ABS_WHEEL,
        "none",
        "no ABS: the driver's pressure ramps to q_max and holds",
        params=(AMPLITUDE,),
    )
)
register(
    ControllerSpec(
        ABS_WHEEL,
        "pid",
        "PID on the slip error e = S_target - S (derlsp-ao-abs eq. 12), filtered derivative "
        "without kick, conditional-integration anti-windup",
        gains=(
            GainSpec(
                "kp",
                "1/(slip)",
                5000.0,
                0.0,
                1e4,
                "proportional gain (acts like an integral "
                "gain on pressure: the actuator integrates)",
            ),
            GainSpec("ki", "1/(slip s)", 0.0, 0.0, 1e4, "integral gain"),
            GainSpec(
                "kd",
                "s/(slip)",
                230.0,
                0.0,
                1e3,
                "derivative gain (acts like a proportional gain on pressure)",
            ),
        ),
        params=(
            ParamSpec("n_filter", "rad/s", 100.0, "derivative filter coefficient N", positive=True),
        ),
    )
)
register(
    ControllerSpec(
        ABS_WHEEL,
        "bang-bang",
        "sldemo's controller: u = amplitude * sign(S_target - S), sampled every ts_s",
        params=(AMPLITUDE, SAMPLE_PERIOD),
    )
)
register(
    ControllerSpec(
        ABS_WHEEL,
        "threshold",
        "rule-based ABS: wheel deceleration/acceleration and slip thresholds drive pressure "
        "build, hold, dump, recover and slow-build phases (see docs/abs.md)",
        params=(
            AMPLITUDE,
            SAMPLE_PERIOD,
            ParamSpec(
                "decel_threshold_m_s2",
                "m/s^2",
                15.0,
                "-a: wheel circumferential deceleration that stops the build-up",
                positive=True,
            ),
            ParamSpec(
                "accel_threshold_m_s2",
                "m/s^2",
                10.0,
                "+a: wheel re-acceleration held before building again",
                positive=True,
            ),
            ParamSpec(
                "slip_margin", "-", 0.05, "dump when slip exceeds target + margin", positive=True
            ),
            ParamSpec(
                "slow_fraction",
                "-",
                0.25,
                "slow build rate as a fraction of amplitude",
                positive=True,
            ),
        ),
    )
)

_RULEBASE_NOTE = "built-in rule base name or a TOML file (`chassistune fuzzy show NAME`)"
_KE = GainSpec(
    "ke",
    "1/(slip)",
    15.0,
    0.1,
    100.0,
    "quantization factor of the slip error e into the rule base's input universe",
)
_KEC = GainSpec(
    "kec",
    "s/(slip)",
    0.3,
    1e-3,
    10.0,
    "quantization factor of de/dt (filtered) into the rule base's input universe",
)

register(
    ControllerSpec(
        ABS_WHEEL,
        "fuzzy-pid",
        "fuzzy self-tuning PID (deffao-vehicle-abs): gains scheduled from e and de/dt by a 7x7 "
        "rule base, kp = kp0 + ku_p * out_kp (likewise ki, kd), sampled every ts_s",
        gains=(
            _KE,
            _KEC,
            GainSpec("ku_p", "1/(slip)", 4000.0, 0.0, 1e4, "output scale of the kp rule table"),
            GainSpec("ku_i", "1/(slip s)", 0.0, 0.0, 1e4, "output scale of the ki rule table"),
            GainSpec("ku_d", "s/(slip)", 100.0, 0.0, 1e3, "output scale of the kd rule table"),
            GainSpec("kp0", "1/(slip)", 3000.0, 0.0, 1e4, "base proportional gain"),
            GainSpec("ki0", "1/(slip s)", 0.0, 0.0, 1e4, "base integral gain"),
            GainSpec("kd0", "s/(slip)", 180.0, 0.0, 1e3, "base derivative gain"),
        ),
        params=(
            ParamSpec("rulebase", "-", "deffao", _RULEBASE_NOTE),
            ParamSpec("n_filter", "rad/s", 100.0, "derivative filter coefficient N", positive=True),
            SAMPLE_PERIOD,
        ),
    )
)
register(
    ControllerSpec(
        ABS_WHEEL,
        "fuzzy-immune-pid",
        "fuzzy immune PID (fuzzy-immune-abs): incremental PID with immune gain "
        "kp1 = k_immune (1 - eta f(e, de/dt)), sampled every ts_s",
        gains=(
            GainSpec(
                "k_immune",
                "1/(slip)",
                1000.0,
                0.0,
                1e4,
                "immune proportional gain K (not the actuator's gain)",
            ),
            GainSpec("eta", "-", 0.5, 0.0, 0.99, "immune suppression factor (kp1 > 0 needs < 1)"),
            GainSpec("ki", "1/(slip s)", 0.0, 0.0, 1e4, "integral gain of the incremental law"),
            GainSpec("kd", "s/(slip)", 50.0, 0.0, 1e3, "derivative gain of the incremental law"),
            GainSpec("ke", "1/(slip)", 5.0, 0.1, 100.0, "quantization factor of e into [-1, 1]"),
            GainSpec(
                "kec", "s/(slip)", 0.1, 1e-3, 10.0, "quantization factor of de/dt into [-1, 1]"
            ),
        ),
        params=(
            ParamSpec("rulebase", "-", "immune", _RULEBASE_NOTE),
            SAMPLE_PERIOD,
        ),
    )
)


# -- quarter-car -------------------------------------------------------------------------------

PAPER_BOX: tuple[tuple[float, float], ...] = ((0.0, 500.0),) * 3
"""Jing and Xu 2023 (iabc-suspension) section 4.2: kp, ki, kd in [0, 500]."""

FEEDBACK = ParamSpec(
    "feedback",
    "-",
    "body_velocity",
    "signal y of e = 0 - y",
    choices=("body_velocity", "body_displacement", "body_acceleration", "suspension_travel"),
)
N_FILTER = ParamSpec(
    "n_filter",
    "rad/s",
    100.0,
    "derivative filter coefficient N: kd N s / (s + N) acts on e (Simulink's PID default)",
    positive=True,
)

register(
    ControllerSpec(QUARTER_CAR, "passive", "passive suspension: spring and damper only, u = 0")
)
register(
    ControllerSpec(
        QUARTER_CAR,
        "pid",
        "PID on e = 0 - y, u = kp e + ki int(e) + kd N s/(s + N) e, + on the body, - on the wheel "
        "(iabc-suspension eq. 4 with the stabilizing sign); units for feedback=body_velocity",
        gains=(
            GainSpec(
                "kp",
                "N s/m",
                500.0,
                0.0,
                1e4,
                "proportional gain (sky-hook damping on body velocity)",
            ),
            GainSpec("ki", "N/m", 500.0, 0.0, 1e5, "integral gain (sky spring: int(vs) = zs)"),
            GainSpec("kd", "N s^2/m", 100.0, 0.0, 1e3, "derivative gain (sky inertance, kg)"),
        ),
        params=(FEEDBACK, N_FILTER),
    )
)
register(
    ControllerSpec(
        QUARTER_CAR,
        "skyhook",
        "classic sky-hook damper u = -c_sky zs' (body absolute velocity), beside the passive "
        "damper",
        gains=(GainSpec("c_sky", "N s/m", 1000.0, 0.0, 1e4, "sky-hook damping coefficient"),),
    )
)


# -- abs-vehicle: the wheel laws' vehicle entries (gains, bounds, defaults) ---------------------
from chassistune.controllers import vehicle_specs as _vehicle_specs  # noqa: E402, F401
