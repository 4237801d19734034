"""Compiling a kernel module's functions with numba, its numpy code staying the fallback.

numba is a dependency in ``package.xml`` (the Addon Manager installs it) but not a hard
one: each kernel module (:mod:`.opw_kernel`, :mod:`.spherical_wrist_kernel`,
:mod:`.offset_wrist_kernel`, :mod:`.offset_wrist_polish_kernel`,
:mod:`.singularity_kernel`) compiles its functions in place on first use with
:func:`compile_in_place`; where numba is missing, switched off or fails, the module
keeps its Python functions and the caller runs its numpy code.
"""

import os

#: Set to "0" to run the numpy code even when numba is installed (tests, bench).
ENVIRONMENT_SWITCH = "CADROBOT_NUMBA"


def compile_in_place(namespace, names, warm_up, inlined=()):
    """Replace functions of a module by their numba compilations, and load them now.

    Parameters
    ----------
    namespace : dict
        The module's ``globals()``.
    names : sequence of str
        The functions to compile (numba's cache keeps them per installation).
    warm_up : callable
        Called with no argument once they are replaced: a call of the kernel on a
        tiny input, which compiles or loads every function.
    inlined : sequence of str
        Those of `names` compiled with ``inline="always"``.

    Returns
    -------
    str
        "" when compiled, else why not (the Python functions are then put back).
    """
    if os.environ.get(ENVIRONMENT_SWITCH, "1") == "0":
        return "switched off by %s=0" % ENVIRONMENT_SWITCH
    python = {name: namespace[name] for name in names}
    try:
        import numba
        inline = numba.njit(cache=True, inline="always", error_model="numpy")
        compiled = numba.njit(cache=True, nogil=True, error_model="numpy")
        for name, function in python.items():
            namespace[name] = (inline if name in inlined else compiled)(function)
        warm_up()
    except Exception as exc:  # noqa: BLE001 - an unusable numba raises anything
        namespace.update(python)
        return "%s: %s" % (type(exc).__name__, exc)
    return ""


def available(namespace, compile_kernel):
    """Whether a kernel module's compiled functions can be used; compiles them once.

    The first call runs `compile_kernel` (the module's ``_compile``: ""
    or why not) and keeps its answer in the module's ``why_not``, so a failure
    falls back to the numpy code from then on and says why.

    Parameters
    ----------
    namespace : dict
        The module's ``globals()`` (holding ``why_not``: None until the first call).
    compile_kernel : callable
        Takes no argument, returns "" or why not.

    Returns
    -------
    bool
    """
    if namespace["why_not"] is None:
        namespace["why_not"] = compile_kernel()
    return namespace["why_not"] == ""
