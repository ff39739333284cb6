"""Controllers of the single-wheel ABS plant, with their gains and bounds (DESIGN 4)."""

from __future__ import annotations

from chassistune.controllers.registry import (
    ControllerSpec,
    GainSpec,
    ParamSpec,
    for_plant,
    register,
)
from chassistune.controllers.registry import get as _get

PLANT = "abs-wheel"

AMPLITUDE = ParamSpec(
    "amplitude", "-", None,
    "pressure command magnitude (rate K*amplitude); default reaches q_max in 0.15 s",
    positive=True,
)

SAMPLE_PERIOD = ParamSpec(
    "ts_s", "s", 1e-3,
    "sample period of the switching law (rounded to whole integration steps, at least one)",
    positive=True,
)

register(ControllerSpec(PLANT, "none", "no ABS: the driver's pressure ramps to q_max and holds",
                        params=(AMPLITUDE,)))
register(ControllerSpec(
    PLANT, "pid",
    "PID on the slip error e = S_target - S (seed 000 eq. 12), filtered derivative without kick, "
    "conditional-integration anti-windup",
    gains=(
        GainSpec("kp", "1/(slip)", 5000.0, 0.0, 1e4, "proportional gain (acts like an integral "
                 "gain on pressure: the actuator integrates)"),
        GainSpec("ki", "1/(slip s)", 0.0, 0.0, 1e4, "integral gain"),
        GainSpec("kd", "s/(slip)", 230.0, 0.0, 1e3, "derivative gain (acts like a proportional "
                 "gain on pressure)"),
    ),
    params=(ParamSpec("n_filter", "rad/s", 100.0, "derivative filter coefficient N",
                      positive=True),),
))
register(ControllerSpec(
    PLANT, "bang-bang",
    "sldemo's controller: u = amplitude * sign(S_target - S), sampled every ts_s",
    params=(AMPLITUDE, SAMPLE_PERIOD),
))
register(ControllerSpec(
    PLANT, "threshold",
    "rule-based ABS: wheel deceleration/acceleration and slip thresholds drive pressure "
    "build, hold, dump, recover and slow-build phases (see docs/abs.md)",
    params=(
        AMPLITUDE,
        SAMPLE_PERIOD,
        ParamSpec("decel_threshold_m_s2", "m/s^2", 15.0,
                  "-a: wheel circumferential deceleration that stops the build-up", positive=True),
        ParamSpec("accel_threshold_m_s2", "m/s^2", 10.0,
                  "+a: wheel re-acceleration held before building again", positive=True),
        ParamSpec("slip_margin", "-", 0.05, "dump when slip exceeds target + margin",
                  positive=True),
        ParamSpec("slow_fraction", "-", 0.25, "slow build rate as a fraction of amplitude",
                  positive=True),
    ),
))


def get(name: str) -> ControllerSpec:
    """The abs-wheel controller `name`."""
    return _get(PLANT, name)


def names() -> list[str]:
    return [s.name for s in for_plant(PLANT)]

_RULEBASE_NOTE = "built-in rule base name or a TOML file (`chassistune fuzzy show NAME`)"
_KE = GainSpec("ke", "1/(slip)", 15.0, 0.1, 100.0,
               "quantization factor of the slip error e into the rule base's input universe")
_KEC = GainSpec("kec", "s/(slip)", 0.3, 1e-3, 10.0,
                "quantization factor of de/dt (filtered) into the rule base's input universe")

register(ControllerSpec(
    PLANT, "fuzzy-pid",
    "fuzzy self-tuning PID (seed 003): gains scheduled from e and de/dt by a 7x7 rule base, "
    "kp = kp0 + ku_p * out_kp (likewise ki, kd), sampled every ts_s",
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
))
register(ControllerSpec(
    PLANT, "fuzzy-immune-pid",
    "fuzzy immune PID (seed 004): incremental PID with immune gain "
    "kp1 = k_immune (1 - eta f(e, de/dt)), sampled every ts_s",
    gains=(
        GainSpec("k_immune", "1/(slip)", 1000.0, 0.0, 1e4,
                 "immune proportional gain K (not the actuator's gain)"),
        GainSpec("eta", "-", 0.5, 0.0, 0.99, "immune suppression factor (kp1 > 0 needs < 1)"),
        GainSpec("ki", "1/(slip s)", 0.0, 0.0, 1e4, "integral gain of the incremental law"),
        GainSpec("kd", "s/(slip)", 50.0, 0.0, 1e3, "derivative gain of the incremental law"),
        GainSpec("ke", "1/(slip)", 5.0, 0.1, 100.0, "quantization factor of e into [-1, 1]"),
        GainSpec("kec", "s/(slip)", 0.1, 1e-3, 10.0, "quantization factor of de/dt into [-1, 1]"),
    ),
    params=(
        ParamSpec("rulebase", "-", "immune", _RULEBASE_NOTE),
        SAMPLE_PERIOD,
    ),
))
