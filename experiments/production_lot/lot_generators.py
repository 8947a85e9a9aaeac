"""Two independent generators of a production lot of open-loop FOGs (issue 33, item 6), and the planted defects.

A lot is a list of units; each unit is a sensor config (the YAML `gyrosid simulate --sensor` takes) drawn from a
type with unit-to-unit variation, plus the truth of its draw. The lot model in gyrosid must not assume either
form, so the two families differ in their parameterisation and in their modes:

  A "type draws": configs/sensors/open_loop_fog.yaml with five multiplicative/additive modes per unit -
      the whole scale-factor surface x exp(0.3 z1), the bias-temperature coefficients x exp(0.4 z2),
      the constant bias + 5 z3 deg/h, the white noise x exp(0.3 z4), a Shupe coefficient 2 exp(0.2 z5)
      deg/h per (deg C/min). The grid values are the reference's (a rank-one surface mode).
  B "independent family": the surface from its own law, seven additive modes with unit-level normal
      coefficients (ppm, u = omega / 100 deg/s, dT = T - 25 C):
          dSF = a0 + a1 u^2 + a2 u + a3 u^3 + a4 dT u^2 + a5 dT + a6 dT^2 u^2
      evaluated at the reference grid's nodes; a cubic bias with unit-level normal coefficients; white noise
      drawn from a gamma law; a normal Shupe coefficient; and a normal chamber-to-probe lag (which moves the
      recorded temperatures, not the error model).

Defects (planted by the lot, not by a generator's draw; each unit's other draws are unchanged):
  shupe_doubled  the Shupe coefficient at twice the type's value;
  ripple         40 ppm sin(pi omega / 20 deg/s) added to the surface at every temperature - written on a
                 5-deg/s rate grid (the reference grid's nodes at multiples of 20 deg/s are the ripple's zeros);
  noise_3x       white noise at three times the type's level.
"""
import os

import numpy as np
import yaml
from scipy.interpolate import CubicSpline

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
REFERENCE = os.path.join(ROOT, "configs", "sensors", "open_loop_fog.yaml")

DEFECTS = ("shupe_doubled", "ripple", "noise_3x")
RIPPLE_PPM = 40.0
RIPPLE_HALF_PERIOD_DPS = 20.0
DENSE_RATES_DPS = [float(r) for r in range(-100, 101, 5)]  # the ripple unit's rate grid


def ripple_ppm(rates_dps):
    return RIPPLE_PPM * np.sin(np.pi * np.asarray(rates_dps, dtype=float) / RIPPLE_HALF_PERIOD_DPS)


def unit_rng(family, lot_seed, index):
    """The random stream of one unit: independent across families, lots and units, the same on every rerun."""
    return np.random.default_rng([ord(family), lot_seed, index])


class TypeDraws:
    """Generator A: log-normal factors and an additive bias around the reference config."""
    family = "A"
    SURFACE_LOG_SD = 0.3
    BIAS_TEMPERATURE_LOG_SD = 0.4
    BIAS_CONSTANT_SD_DPH = 5.0
    WHITE_LOG_SD = 0.3
    SHUPE_TYPE = 2.0  # deg/h per (deg C/min)
    SHUPE_LOG_SD = 0.2

    def __init__(self):
        with open(REFERENCE) as f:
            self.base = yaml.safe_load(f)
        self.white_type = float(self.base["noise"]["white_dph_at_1hz"])

    def unit(self, rng, defect=None):
        z = rng.standard_normal(5)  # always five draws: a defect does not change the unit's other terms
        doc = yaml.safe_load(yaml.safe_dump(self.base))
        factors = {"surface": float(np.exp(self.SURFACE_LOG_SD * z[0])),
                   "bias_temperature": float(np.exp(self.BIAS_TEMPERATURE_LOG_SD * z[1])),
                   "white": float(np.exp(self.WHITE_LOG_SD * z[3]))}
        surface = doc["scale_factor"]["surface"]
        surface["error_ppm"] = [[v * factors["surface"] for v in row] for row in surface["error_ppm"]]
        bias = doc["bias"]
        bias["temperature"]["coefficients_dph"] = [c * factors["bias_temperature"] for c in bias["temperature"]["coefficients_dph"]]
        bias["constant_dph"] = float(bias["constant_dph"] + self.BIAS_CONSTANT_SD_DPH * z[2])
        doc["noise"]["white_dph_at_1hz"] = self.white_type * factors["white"]
        doc["shupe_dph_per_c_per_min"] = float(self.SHUPE_TYPE * np.exp(self.SHUPE_LOG_SD * z[4]))
        if defect == "shupe_doubled":
            doc["shupe_dph_per_c_per_min"] = 2.0 * self.SHUPE_TYPE
        elif defect == "noise_3x":
            doc["noise"]["white_dph_at_1hz"] = 3.0 * self.white_type
        elif defect == "ripple":
            self._add_ripple(surface)
        elif defect is not None:
            raise ValueError("unknown defect %r" % defect)
        truth = {"surface_factor": factors["surface"], "bias_temperature_factor": factors["bias_temperature"],
                 "bias_constant_dph": bias["constant_dph"], "white_dph_at_1hz": doc["noise"]["white_dph_at_1hz"],
                 "shupe_dph_per_c_per_min": doc["shupe_dph_per_c_per_min"]}
        return doc, truth

    @staticmethod
    def _add_ripple(surface):
        """The grid's rows resampled on DENSE_RATES_DPS by the simulator's own interpolant along the rate (the
        not-a-knot cubic spline: at a grid temperature the tensor-product spline is its row's spline), plus the
        ripple."""
        rates = np.asarray(surface["rates_dps"], dtype=float)
        rows = []
        for row in surface["error_ppm"]:
            spline = CubicSpline(rates, np.asarray(row, dtype=float), bc_type="not-a-knot")
            rows.append([float(v) for v in spline(DENSE_RATES_DPS) + ripple_ppm(DENSE_RATES_DPS)])
        surface["rates_dps"] = list(DENSE_RATES_DPS)
        surface["error_ppm"] = rows


class IndependentFamily:
    """Generator B: a scale-factor law with unit-level normal coefficients, written from scratch."""
    family = "B"
    TEMPERATURES_C = [-60.0, -20.0, 0.0, 20.0, 25.0, 40.0, 60.0, 80.0]
    RATES_DPS = [-100.0, -80.0, -60.0, -40.0, -20.0, -10.0, 10.0, 20.0, 40.0, 60.0, 80.0, 100.0]
    # (mean, sd) of a0..a6, ppm, in the law of the module's docstring
    SURFACE = [(0.0, 20.0), (-600.0, 60.0), (50.0, 15.0), (20.0, 8.0), (-4.0, 1.0), (0.0, 1.5), (-0.04, 0.015)]
    BIAS = [(-10.0, 4.0), (0.10, 0.03), (-0.002, 0.0008), (3e-5, 1e-5)]  # c0..c3, deg/h per (deg C)^i
    WHITE_TYPE_DPH = 8.0
    WHITE_GAMMA_SHAPE = 40.0  # coefficient of variation 1/sqrt(40) = 0.16
    SHUPE = (1.5, 0.3)        # deg/h per (deg C/min)
    TAU_S = (300.0, 40.0)

    def unit(self, rng, defect=None):
        a = np.array([rng.normal(m, s) for m, s in self.SURFACE])
        c = np.array([rng.normal(m, s) for m, s in self.BIAS])
        white = float(rng.gamma(self.WHITE_GAMMA_SHAPE, self.WHITE_TYPE_DPH / self.WHITE_GAMMA_SHAPE))
        shupe = float(rng.normal(*self.SHUPE))
        tau = float(rng.normal(*self.TAU_S))
        rates = self.RATES_DPS
        extra = np.zeros(len(rates))
        if defect == "shupe_doubled":
            shupe = 2.0 * self.SHUPE[0]
        elif defect == "noise_3x":
            white = 3.0 * self.WHITE_TYPE_DPH
        elif defect == "ripple":
            rates = DENSE_RATES_DPS
            extra = ripple_ppm(rates)
        elif defect is not None:
            raise ValueError("unknown defect %r" % defect)
        surface = self.surface_ppm(a, self.TEMPERATURES_C, rates) + extra[None, :]
        doc = {
            "kind": "gyro",
            "name": "independent-family FOG unit",
            "bias": {"constant_dph": float(c[0]),
                     "temperature": {"reference_c": 25, "coefficients_dph": [0.0] + [float(x) for x in c[1:]]}},
            "scale_factor": {"surface": {"temperatures_c": list(self.TEMPERATURES_C), "rates_dps": list(rates),
                                         "error_ppm": [[float(v) for v in row] for row in surface], "outside": "clamp"}},
            "shupe_dph_per_c_per_min": shupe,
            "noise": {"white_dph_at_1hz": white},
            "thermal": {"tau_s": tau, "delay_s": 0, "coil_tau_s": 0},
            "range_dps": 500,
        }
        truth = {"surface_coefficients_ppm": [float(x) for x in a], "bias_coefficients_dph": [float(x) for x in c],
                 "white_dph_at_1hz": white, "shupe_dph_per_c_per_min": shupe, "tau_s": tau}
        return doc, truth

    @staticmethod
    def surface_ppm(a, temperatures_c, rates_dps):
        dT = np.asarray(temperatures_c, dtype=float)[:, None] - 25.0
        u = np.asarray(rates_dps, dtype=float)[None, :] / 100.0
        return (a[0] + a[1] * u ** 2 + a[2] * u + a[3] * u ** 3 + a[4] * dT * u ** 2 + a[5] * dT
                + a[6] * dT ** 2 * u ** 2)


GENERATORS = {"A": TypeDraws, "B": IndependentFamily}


def plant_defects(n_units, first_screened, share, seed):
    """{unit index: defect}: round(share * n_units) defective units among indices >= first_screened (the training
    sample stays clean), the defect types in turn."""
    n = int(round(share * n_units))
    rng = np.random.default_rng([seed, n_units])
    idx = sorted(int(i) for i in rng.choice(np.arange(first_screened, n_units), size=n, replace=False))
    order = rng.permutation(n)
    return {idx[k]: DEFECTS[order[k] % len(DEFECTS)] for k in range(n)}


def write_unit(generator, lot_seed, index, path, defect=None):
    """Draws unit `index` of lot `lot_seed`, writes its sensor config to `path` (atomically), returns its truth."""
    doc, truth = generator.unit(unit_rng(generator.family, lot_seed, index), defect)
    doc["name"] = "%s lot %d unit %d%s" % (doc["name"], lot_seed, index, " (defect: %s)" % defect if defect else "")
    truth["defect"] = defect
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("# Drawn by experiments/production_lot/lot_generators.py: family %s, lot %d, unit %d\n" % (generator.family, lot_seed, index))
        yaml.safe_dump(doc, f, sort_keys=False, default_flow_style=None, width=200)
    os.replace(tmp, path)
    return truth
