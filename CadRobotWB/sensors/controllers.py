"""Force controllers of profile following: PI and Fuzzy-PI (paper 4.2).

Each controller runs once per control period on the force error
``e = F_set - F_measured`` (N) and returns the *increment* of the robot's
displacement along the tool axis (mm, positive = press further in): the
incremental (velocity) form the robot takes as a relative path correction
every period. Each keeps the displacement it has commanded so far in
:attr:`displacement_mm` and never lets it leave ``+-integral_limit`` (the
anti-windup), and no single increment exceeds ``+-output_limit``.

::

    controller = make_controller("fuzzy_pi", **fuzzy_pi_tuning(20.0, 20.0))
    increment_mm = controller.step(error_n, 0.05)

Tuning from the contact stiffness k (N/mm) and the period T (s): with the
contact a spring, one period's increment ``du`` changes the force by
``k du``, so the loop gain of each term is a fraction of what would cancel the
error in one period: ``ki T k = INTEGRAL_LOOP_GAIN`` and ``kp k =
PROPORTIONAL_LOOP_GAIN`` (values chosen for a robot lag of about one period,
see :func:`pi_tuning`).

Pure numpy: never imports FreeCAD.
"""

import numpy as np

from ..errors import InputError, UnknownNameError

#: Fraction of the force error the integral term removes per period (ki T k).
INTEGRAL_LOOP_GAIN = 0.4
#: Fraction of a force change the proportional term takes back (kp k).
PROPORTIONAL_LOOP_GAIN = 0.5

CONTROLLER_NAMES = ("pi", "fuzzy_pi", "none")


class _Incremental:
    """What every controller shares: limits, the displacement so far."""

    name = ""

    def __init__(self, output_limit, integral_limit):
        if not output_limit > 0 or not integral_limit > 0:
            raise InputError("A controller needs an output limit > 0 mm and an integral "
                             "limit > 0 mm, got %r and %r." % (output_limit, integral_limit))
        self.output_limit = float(output_limit)
        self.integral_limit = float(integral_limit)
        self.reset()

    def reset(self, displacement_mm=0.0):
        """Forget the past errors; the displacement so far becomes `displacement_mm`."""
        self.displacement_mm = float(displacement_mm)
        self.previous_error_n = 0.0

    def step(self, error_n, dt_s):
        """One control period.

        Parameters
        ----------
        error_n : float
            Force error ``F_set - F_measured``, N.
        dt_s : float
            Control period, s.

        Returns
        -------
        float
            Displacement increment along the tool axis, mm (after the limits).
        """
        raw = self._raw_increment(float(error_n), float(dt_s))
        self.previous_error_n = float(error_n)
        wanted = self.displacement_mm + _clip(raw, self.output_limit)
        new = _clip(wanted, self.integral_limit)
        increment = new - self.displacement_mm
        self.displacement_mm = new
        return increment

    def _raw_increment(self, error_n, dt_s):
        raise NotImplementedError


def _clip(value, limit):
    """float `value` clipped to [-limit, limit] (np.clip is slow for one number)."""
    return float(min(max(value, -limit), limit))


class PIController(_Incremental):
    """PI in incremental form: ``du_k = kp (e_k - e_{k-1}) + ki T e_k``.

    Summed over the periods this is the positional PI ``u = kp e + ki sum(e T)``
    (with ``e_{-1} = 0`` after a reset).

    Parameters
    ----------
    kp : float
        Proportional gain, mm/N.
    ki : float
        Integral gain, mm/(N·s).
    output_limit : float
        Largest increment per period, mm.
    integral_limit : float
        Largest displacement the controller may accumulate, mm.
    """

    name = "pi"

    def __init__(self, kp, ki, output_limit, integral_limit):
        if kp < 0 or ki < 0:
            raise InputError("PI gains must be >= 0, got kp=%r, ki=%r." % (kp, ki))
        self.kp = float(kp)
        self.ki = float(ki)
        super().__init__(output_limit, integral_limit)

    def _raw_increment(self, error_n, dt_s):
        return self.kp * (error_n - self.previous_error_n) + self.ki * dt_s * error_n


#: Linguistic terms, index -3..3 from "negative big" to "positive big".
LABELS = ("NB", "NM", "NS", "ZE", "PS", "PM", "PB")
#: Centres of the terms on the normalised universe [-1, 1].
TERM_CENTRES = np.linspace(-1.0, 1.0, 7)
#: Half-width of each triangular term (neighbours cross at membership 0.5).
TERM_HALF_WIDTH = 1.0 / 3.0

#: The rule base: output term for (error term = row, change-of-error term =
#: column), as indices into LABELS. Rows and columns are NB..PB.
RULE_TABLE = np.array([
    # de: NB NM NS ZE PS PM PB        e:
    [0, 0, 0, 0, 1, 2, 3],          # NB
    [0, 0, 0, 1, 2, 3, 4],          # NM
    [0, 0, 1, 2, 3, 4, 5],          # NS
    [0, 1, 2, 3, 4, 5, 6],          # ZE
    [1, 2, 3, 4, 5, 6, 6],          # PS
    [2, 3, 4, 5, 6, 6, 6],          # PM
    [3, 4, 5, 6, 6, 6, 6],          # PB
])

#: Where the output's aggregated membership is sampled for the centroid: the
#: universe plus the outer half of the end terms (so "PB" alone gives 1).
_OUTPUT_GRID = np.linspace(-1.0 - TERM_HALF_WIDTH, 1.0 + TERM_HALF_WIDTH, 2001)
#: Each output term's membership on the grid, (7, G).
_OUTPUT_SHAPES = np.clip(1.0 - np.abs(_OUTPUT_GRID[None] - TERM_CENTRES[:, None]) / TERM_HALF_WIDTH,
                         0.0, None)


def memberships(x):
    """Degrees (7,) of x in NB..PB: triangles, shoulders at the ends.

    `x` is clipped to [-1, 1] first, so beyond the universe the end term
    holds with degree 1.
    """
    x = _clip(x, 1.0)
    return np.minimum(np.maximum(1.0 - np.abs(x - TERM_CENTRES) / TERM_HALF_WIDTH, 0.0), 1.0)


def fuzzy_increment(error, change):
    """The rule base's answer for normalised inputs, in [-1, 1].

    Mamdani inference: rule strength = min of the two memberships, each
    output term clipped at the strongest rule that names it (max), the
    clipped terms merged (max), and the centroid of the merged shape is the
    answer.

    Parameters
    ----------
    error, change : float
        Force error and its change over one period, each divided by its
        scale (values beyond +-1 count as +-1).

    Returns
    -------
    float
        Increment divided by its scale.
    """
    term_strength = _term_strengths(memberships(error), memberships(change))
    # Terms no rule fires clip to 0 and change nothing in the max (the others are >= 0).
    fired = sorted(term_strength)
    clip_at = np.array([term_strength[term] for term in fired])[:, None]
    merged = np.max(np.minimum(_OUTPUT_SHAPES[fired], clip_at), axis=0)
    return float(np.sum(merged * _OUTPUT_GRID) / np.sum(merged))


def _term_strengths(error_degrees, change_degrees):
    """{output term: strength of the strongest rule naming it} for the rules that fire.

    Rule (e, de) fires with min of the two degrees (> 0 for at most 2 x 2
    pairs of neighbouring terms).
    """
    strengths = {}
    error_terms, change_terms = np.flatnonzero(error_degrees), np.flatnonzero(change_degrees)
    for e, e_degree in zip(error_terms.tolist(), error_degrees[error_terms].tolist()):
        for de, de_degree in zip(change_terms.tolist(), change_degrees[change_terms].tolist()):
            term = int(RULE_TABLE[e, de])
            strengths[term] = max(strengths.get(term, 0.0), min(e_degree, de_degree))
    return strengths


class FuzzyPIController(_Incremental):
    """Fuzzy-PI in incremental form: ``du = Gu * fuzzy(e / Ge, de / Gde)``.

    Inputs: the force error ``e`` and its change over one period
    ``de = e_k - e_{k-1}``, each divided by its scale and clipped to
    [-1, 1]; seven triangular terms on each (centres at -1, -2/3, ..., 1,
    neighbours crossing at 0.5). Output: the displacement increment over
    its scale, seven terms of the same shape, centroid defuzzification (see
    :func:`fuzzy_increment`).

    Rule base (output term for each error row and change column; the
    MacVicar-Whelan diagonal table: press more when the force is too low
    and not already rising, back off when it is too high and not already
    falling, do nothing on the diagonal where the two cancel)::

                          change of error de
                   NB   NM   NS   ZE   PS   PM   PB
        error  NB  NB   NB   NB   NB   NM   NS   ZE
            e  NM  NB   NB   NB   NM   NS   ZE   PS
               NS  NB   NB   NM   NS   ZE   PS   PM
               ZE  NB   NM   NS   ZE   PS   PM   PB
               PS  NM   NS   ZE   PS   PM   PB   PB
               PM  NS   ZE   PS   PM   PB   PB   PB
               PB  ZE   PS   PM   PB   PB   PB   PB

    Along each input axis the surface is the line ``E`` (``dE``) to within
    0.02 and exact at the term centres, so it acts like a PI with
    ``kp = Gu / Gde`` and ``ki T = Gu / Ge``, saturating at ``Gu``. What
    max-min inference adds: near the origin the slope rises to 1.5 along an
    axis and 2 along the diagonal (a term firing weakly, clipped low, still
    spans its whole base, so it pulls the centroid more than its degree
    says), so the controller is stiffer for small errors; and the surface
    is monotonic only to within 0.02 (it may dip by up to 0.02 of Gu as the
    change of error grows).

    Parameters
    ----------
    error_scale : float
        Ge, force error mapped to 1 ("PB"), N.
    change_scale : float
        Gde, change of the error per period mapped to 1, N.
    output_scale : float
        Gu, increment for an output of 1, mm.
    output_limit : float
        Largest increment per period, mm.
    integral_limit : float
        Largest displacement the controller may accumulate, mm.
    """

    name = "fuzzy_pi"

    def __init__(self, error_scale, change_scale, output_scale, output_limit, integral_limit):
        if not error_scale > 0 or not change_scale > 0 or not output_scale > 0:
            raise InputError("Fuzzy-PI scales must be > 0, got Ge=%r, Gde=%r, Gu=%r."
                             % (error_scale, change_scale, output_scale))
        self.error_scale = float(error_scale)
        self.change_scale = float(change_scale)
        self.output_scale = float(output_scale)
        super().__init__(output_limit, integral_limit)

    def _raw_increment(self, error_n, dt_s):
        change = error_n - self.previous_error_n
        return self.output_scale * fuzzy_increment(error_n / self.error_scale,
                                                   change / self.change_scale)


class OpenLoop(_Incremental):
    """No controller: the program runs as drawn (every increment is 0)."""

    name = "none"

    def __init__(self, output_limit=1.0, integral_limit=1.0):
        super().__init__(output_limit, integral_limit)

    def _raw_increment(self, error_n, dt_s):
        return 0.0


def pi_tuning(stiffness_n_mm, rate_hz, max_step_mm=0.3, max_correction_mm=15.0):
    """PI parameters for a contact of stiffness k at a control rate.

    ``ki = INTEGRAL_LOOP_GAIN / (k T)`` and ``kp = PROPORTIONAL_LOOP_GAIN / k``
    with ``T = 1 / rate_hz``. The proportional term on the *change* of the
    force acts as damping at the impact, the integral term removes a
    quarter of the error per period; with the robot lagging about one
    period behind its command this settles without ringing.

    Parameters
    ----------
    stiffness_n_mm : float
        Contact stiffness, N/mm.
    rate_hz : float
        Control rate, Hz.
    max_step_mm : float
        Output limit: the largest correction per period, mm (it also sets the
        approach speed before contact, ``max_step_mm * rate_hz``).
    max_correction_mm : float
        Integral limit, mm.

    Returns
    -------
    dict
        Keyword arguments of :class:`PIController`.
    """
    period_s = 1.0 / rate_hz
    return {"kp": PROPORTIONAL_LOOP_GAIN / stiffness_n_mm,
            "ki": INTEGRAL_LOOP_GAIN / (stiffness_n_mm * period_s),
            "output_limit": max_step_mm, "integral_limit": max_correction_mm}


def fuzzy_pi_tuning(stiffness_n_mm, rate_hz, max_step_mm=0.3, max_correction_mm=15.0):
    """Fuzzy-PI scales with the same small-signal gains as :func:`pi_tuning`.

    ``Gu = max_step_mm`` (the largest increment), ``Ge = Gu / (ki T)`` and
    ``Gde = Gu / kp``: along each input axis the fuzzy surface meets the
    PI's line at every term centre (errors of Ge/3, 2 Ge/3, ...); it is up
    to 1.5 times stiffer for errors below Ge/6, and saturates smoothly.

    Returns
    -------
    dict
        Keyword arguments of :class:`FuzzyPIController`.
    """
    pi = pi_tuning(stiffness_n_mm, rate_hz, max_step_mm, max_correction_mm)
    period_s = 1.0 / rate_hz
    return {"error_scale": max_step_mm / (pi["ki"] * period_s),
            "change_scale": max_step_mm / pi["kp"],
            "output_scale": max_step_mm,
            "output_limit": max_step_mm, "integral_limit": max_correction_mm}


def default_tuning(name, stiffness_n_mm, rate_hz, max_step_mm=0.3, max_correction_mm=15.0):
    """Keyword arguments of :func:`make_controller` for `name` (see the tunings)."""
    if name == "pi":
        return pi_tuning(stiffness_n_mm, rate_hz, max_step_mm, max_correction_mm)
    if name == "fuzzy_pi":
        return fuzzy_pi_tuning(stiffness_n_mm, rate_hz, max_step_mm, max_correction_mm)
    if name == "none":
        return {}
    raise UnknownNameError("Unknown force controller %r: use one of %s."
                           % (name, ", ".join(CONTROLLER_NAMES)))


def make_controller(name, **params):
    """A controller by name: ``"pi"``, ``"fuzzy_pi"`` or ``"none"`` (open loop).

    `params` are the class's keyword arguments (see :func:`default_tuning`).
    """
    classes = {"pi": PIController, "fuzzy_pi": FuzzyPIController, "none": OpenLoop}
    if name not in classes:
        raise UnknownNameError("Unknown force controller %r: use one of %s."
                               % (name, ", ".join(CONTROLLER_NAMES)))
    try:
        return classes[name](**params)
    except TypeError as exc:
        raise InputError("Bad parameters for the %r controller: %s." % (name, exc)) from None
