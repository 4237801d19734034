"""Tracks and positioners a user can pick, with their published data.

INTERFACE (issue 23): :func:`build` and :func:`solids` are what the App layer
calls; the catalog of real mechanisms with sources fills in behind them.
"""

import numpy as np

from ...core import mechanisms as mech
from ...errors import InputError


def _rot_y(deg):
    T = np.eye(4)
    a = np.radians(deg)
    T[:3, :3] = [[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]]
    return T


def _at(x=0.0, y=0.0, z=0.0, T=None):
    T = np.eye(4) if T is None else T.copy()
    T[:3, 3] = (x, y, z)
    return T


def names(kind=None):
    """Catalog names, sorted; only those of `kind` (one of ``core.mechanisms.KINDS``) if given."""
    return []


def build(kind, model=None, name="Positioner", label="", T_u_base=None, drawn_at=None,
          length_mm=None):
    """A Mechanism of `kind`, from the catalog entry `model` or generic values.

    Parameters
    ----------
    kind : str
        ``"track"``, ``"turntable"`` or ``"tilt_turn"``.
    model : str or None
        Catalog name; None: a generic mechanism of that kind.
    name, label : str
    T_u_base : ndarray, shape (4, 4), optional
        Its base in {U}; identity if omitted.
    drawn_at : array_like, shape (K,), optional
        Axis values the document shows; zeros if omitted.
    length_mm : float, optional
        A track's travel (its upper limit), mm.

    Returns
    -------
    core.mechanisms.Mechanism
    """
    if kind not in mech.KINDS:
        raise InputError("Mechanism kind '%s' is unknown: use one of %s."
                         % (kind, ", ".join(mech.KINDS)))
    T_u_base = np.eye(4) if T_u_base is None else np.asarray(T_u_base, dtype=float)
    if kind == mech.TRACK:
        axes = [mech.Axis("travel", mech.LINEAR, _rot_y(90.0), 0.0,
                          float(length_mm or 3000.0), 1000.0, 2000.0)]
        flange = _rot_y(-90.0) @ _at(0, 0, 250.0)
    elif kind == mech.TURNTABLE:
        axes = [mech.Axis("turn", mech.ROTARY, _at(0, 0, 750.0), -3600.0, 3600.0, 90.0, 180.0)]
        flange = np.eye(4)
    else:
        axes = [mech.Axis("tilt", mech.ROTARY, _at(0, 0, 800.0, _rot_y(90.0)), -135.0, 135.0,
                          70.0, 140.0),
                mech.Axis("turn", mech.ROTARY, _rot_y(-90.0), -3600.0, 3600.0, 90.0, 180.0)]
        flange = np.eye(4)
    return mech.Mechanism(name=name, label=label or name, kind=kind, model=model or "",
                          axes=axes, T_last_flange=flange, T_u_base=T_u_base, drawn_at=drawn_at)


def solids(mechanism, values=None):
    """The mechanism's solids at `values` (its drawn pose if None), in {U}.

    Returns
    -------
    list of (vertices, faces)
        vertices : ndarray, shape (V, 3), mm in {U}; faces : ndarray, shape (F, 3), int.
        One mesh per moving body (base first), for the view and the collision checks.
    """
    return []
