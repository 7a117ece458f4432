"""Input distributions of a run: what the study's `vary:` section asked for, as `kanesens run`
records it in the run file's /vary group (one group per input, its attributes `distribution`
and the parameters under their study-file keys: low, high, mean, std, mu, sigma, mode, values,
value).

Each Distribution knows its mean and variance (linear UQ), its CDF (to put Morris steps on the
unit hypercube) and its Poincaré constant C, the smallest C with Var g(X) ≤ C E[g'(X)²] for
every smooth g (the DGSM bound S_Ti ≤ C ν_i / Var y of Sobol' & Kucherenko 2009, Lamboni et
al. 2013):
    uniform(a, b)          C = (b − a)²/π²                 (exact)
    normal(μ, σ)           C = σ²                          (exact)
    truncnormal            C = min(σ², (b − a)²/π²)        (Bakry–Émery; Payne–Weinberger for
                                                            a log-concave density on [a, b])
    triangular(a, c, b)    C = (b − a)²/π²                 (log-concave density: Payne–Weinberger)
    lognormal, choice      none (no Poincaré inequality: heavy tail / discrete)
    fixed                  C = 0
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

KINDS = {"uniform": ("low", "high"), "normal": ("mean", "std"),
         "truncnormal": ("mean", "std", "low", "high"), "lognormal": ("mu", "sigma"),
         "triangular": ("low", "mode", "high"), "choice": ("values",), "fixed": ("value",)}


class StudyError(ValueError):
    """A distribution this package cannot read (unknown kind, missing parameter)."""


@dataclass(frozen=True)
class Distribution:
    name: str
    kind: str
    params: dict = field(default_factory=dict)

    def _scipy(self):
        from scipy import stats  # imported here: it costs a second and most commands skip it
        p = self.params
        if self.kind == "uniform":
            return stats.uniform(loc=p["low"], scale=p["high"] - p["low"])
        if self.kind == "normal":
            return stats.norm(loc=p["mean"], scale=p["std"])
        if self.kind == "truncnormal":
            a = (p["low"] - p["mean"]) / p["std"]
            b = (p["high"] - p["mean"]) / p["std"]
            return stats.truncnorm(a, b, loc=p["mean"], scale=p["std"])
        if self.kind == "lognormal":
            return stats.lognorm(s=p["sigma"], scale=np.exp(p["mu"]))
        if self.kind == "triangular":
            width = p["high"] - p["low"]
            return stats.triang((p["mode"] - p["low"]) / width, loc=p["low"], scale=width)
        return None

    def mean(self) -> float:
        if self.kind == "choice":
            return float(np.mean(self.params["values"]))
        if self.kind == "fixed":
            return float(self.params["value"])
        return float(self._scipy().mean())

    def variance(self) -> float:
        if self.kind == "choice":
            return float(np.var(self.params["values"]))
        if self.kind == "fixed":
            return 0.0
        return float(self._scipy().var())

    def cdf(self, x):
        if self.kind == "choice":
            values = np.sort(np.asarray(self.params["values"], float))
            return np.searchsorted(values, x, side="right") / values.size
        if self.kind == "fixed":
            return np.zeros_like(np.asarray(x, float))
        return self._scipy().cdf(x)

    def poincare_constant(self):
        """(C, reason); C is None where no Poincaré inequality holds."""
        p = self.params
        if self.kind == "uniform":
            return (p["high"] - p["low"]) ** 2 / np.pi ** 2, "(b-a)^2/pi^2"
        if self.kind == "normal":
            return p["std"] ** 2, "sigma^2"
        if self.kind == "truncnormal":
            return min(p["std"] ** 2, (p["high"] - p["low"]) ** 2 / np.pi ** 2), \
                "min(sigma^2, (b-a)^2/pi^2)"
        if self.kind == "triangular":
            return (p["high"] - p["low"]) ** 2 / np.pi ** 2, "(b-a)^2/pi^2 (log-concave)"
        if self.kind == "fixed":
            return 0.0, "fixed input"
        return None, f"{self.kind}: no Poincare inequality, no DGSM bound"


def parse_vary(vary: dict) -> dict:
    """{name: Distribution} from a `vary:` mapping; unknown kinds and missing keys are errors."""
    out = {}
    for name, spec in (vary or {}).items():
        if not isinstance(spec, dict) or "dist" not in spec:
            raise StudyError(f"vary.{name}: expected a mapping with a 'dist' key, got {spec!r}")
        kind = str(spec["dist"]).lower()
        if kind not in KINDS:
            raise StudyError(f"vary.{name}: unknown dist '{kind}'; known: {', '.join(KINDS)}")
        missing = [k for k in KINDS[kind] if k not in spec]
        if missing:
            raise StudyError(f"vary.{name}: dist {kind} needs {', '.join(missing)}")
        params = {k: (list(map(float, spec[k])) if k == "values" else float(spec[k]))
                  for k in KINDS[kind]}
        out[str(name)] = Distribution(str(name), kind, params)
    return out


def from_attributes(vary: dict) -> dict:
    """{name: Distribution} from the /vary group ({name: {"distribution": kind, key: value}},
    as io.open_run puts it in ds.attrs["vary"])."""
    return parse_vary({name: {("dist" if k == "distribution" else k): v for k, v in attrs.items()}
                       for name, attrs in (vary or {}).items()})


def from_study_yaml(text: str) -> dict:
    """Distributions of a run file written before /vary existed: the `vary:` section of the
    study text in its `study_yaml` attribute."""
    if not text:
        return {}
    import yaml  # only for such files
    study = yaml.safe_load(text) or {}
    return parse_vary(study.get("vary") if isinstance(study, dict) else None)
