"""Rules the built-in post-processors share.

Only what is the same rule in several posts lives here: number text without
``-0``, comment text in plain ASCII, identifiers that are unique without
regard to case, file names every OS accepts, the checks every move must
pass, and a few option checks.
What differs between robot languages (identifier length, reserved words,
prefixes, wording of a post's own messages) stays in each post and is
passed in as parameters.

Pure Python/numpy: never imports FreeCAD.
"""

import datetime
import hashlib
import math
import re
import textwrap
import unicodedata

import numpy as np

from .. import command_line
from ..core import program as ir
from ..core import frames, rotations, weld_runs
from ..errors import InputError, PostError, UnknownNameError
from ..robots.catalog import catalog, makers
from ..robots.kinematics.arm_families import chain_parameters
from .output_check import WINDOWS_DEVICE_NAMES, file_stem  # noqa: F401 -- posts' names

# --- numbers -----------------------------------------------------------------


def fixed(value, decimals):
    """Fixed-point text of a number, never ``-0.000``.

    Parameters
    ----------
    value : float
    decimals : int

    Returns
    -------
    str
        ``f"{value:.{decimals}f}"``, without the sign when it rounds to 0.
    """
    text = f"{float(value):.{decimals}f}"
    if float(text) == 0.0:
        text = text.lstrip("-")
    return text


def compact(value, decimals=4):
    """Shortest text of a number to ``decimals`` decimals: 10, 12.5, 0.045.

    Parameters
    ----------
    value : float
    decimals : int, optional

    Returns
    -------
    str
        No trailing zeros or point; ``"0"`` instead of ``"-0"``.
    """
    text = f"{float(value):.{decimals}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def floor_decimals(value, decimals):
    """`value` rounded down to `decimals` decimals: a zone is never written
    larger than asked.

    Parameters
    ----------
    value : float
    decimals : int

    Returns
    -------
    float
        ``0.29996`` -> ``0.2999`` at 4 decimals; ``0.3`` stays ``0.3`` (the
        product is rounded to 6 more decimals first, so float noise such as
        ``0.3 * 1e4 = 2999.9999999999995`` does not cost a step).
    """
    scale = 10.0 ** decimals
    return math.floor(round(float(value) * scale, 6)) / scale


def round_half_up(value):
    """Nearest whole number, halves up (2.5 -> 3).

    Parameters
    ----------
    value : float

    Returns
    -------
    int
    """
    return int(math.floor(float(value) + 0.5))


# --- text --------------------------------------------------------------------

# Control characters that are not white space (white space is folded by comment_text).
_CONTROL_CHARACTERS = re.compile(r"[\x00-\x08\x0e-\x1b\x7f]")


def ascii_text(text):
    """Plain ASCII of a text: accents dropped, other characters ``?``.

    Parameters
    ----------
    text : object
        Converted with ``str``.

    Returns
    -------
    str
        Control characters other than white space (NUL, ESC, ... from a
        label) are ``?`` too: no controller reads them in a program.
    """
    text = unicodedata.normalize("NFKD", str(text))
    text = "".join(c for c in text if not unicodedata.combining(c))
    text = _CONTROL_CHARACTERS.sub("?", text)
    return text.encode("ascii", "replace").decode("ascii")


def comment_text(text, blanks=""):
    """One line of plain ASCII for a comment.

    Parameters
    ----------
    text : object
        Converted with ``str``.
    blanks : str, optional
        Characters the language does not allow in a comment; they become
        spaces.

    Returns
    -------
    str
        :func:`ascii_text` of ``text``, runs of white space folded to one
        space, no leading or trailing space.
    """
    text = ascii_text(text)
    for character in blanks:
        text = text.replace(character, " ")
    return " ".join(text.split())


def path_label(path):
    """A path's label (else its name) as comment text; ``(no name)`` when neither shows.

    Parameters
    ----------
    path : CadRobotWB.core.program.ProgramPath

    Returns
    -------
    str
        Never empty, so a ``Path:`` comment never ends in a space.
    """
    return comment_text(path.label) or comment_text(path.name) or "(no name)"


def wrap_words(text, width):
    """Cut a one-line text into lines of at most ``width`` characters.

    Parameters
    ----------
    text : str
        Words separated by single spaces (see :func:`comment_text`).
    width : int

    Returns
    -------
    list of str
        Cut at spaces where possible; a word longer than ``width`` is cut
        into pieces of ``width`` characters.
    """
    lines, line = [], ""
    for word in text.split(" "):
        while len(word) > width:
            if line:
                lines.append(line)
                line = ""
            lines.append(word[:width])
            word = word[width:]
        if not line:
            line = word
        elif len(line) + 1 + len(word) <= width:
            line += " " + word
        else:
            lines.append(line)
            line = word
    if line:
        lines.append(line)
    return lines


def source_and_robot(program, clean=comment_text):
    """The program's source and robot as comment text.

    Parameters
    ----------
    program : CadRobotWB.core.program.Program
    clean : callable, optional
        The post's comment cleaning, default :func:`comment_text`.

    Returns
    -------
    tuple of str
        ``(source, robot)``, ``"(unknown)"`` for an empty one.
    """
    return (clean(program.source) or "(unknown)",
            clean(program.robot) or "(unknown)")


def post_maker(post_name):
    """The maker whose controllers a built-in post writes for.

    Returns
    -------
    str or None
        As in :mod:`~..robots.catalog.makers` (``"KUKA"`` for ``"kuka_krl"``);
        None for a post no maker takes as its own (a user post).
    """
    for maker in makers.MAKERS:
        if makers.convention(maker).default_post == post_name:
            return maker
    return None


def robot_maker(robot):
    """The maker of catalog robot `robot` as :mod:`~..robots.catalog.makers` spells
    it (its catalog spelling for a maker it does not know); None for a robot not
    in the catalog or without a maker."""
    try:
        manufacturer = catalog.get(robot).manufacturer
    except UnknownNameError:
        return None
    try:
        return makers.convention(manufacturer).maker
    except UnknownNameError:
        return manufacturer or None


def other_maker_note(robot, post_name, controller=None):
    """The sentence a program's header carries when its post is another maker's
    than its robot's, else "".

    Parameters
    ----------
    robot : str
        Catalog name of the cell's robot (``Program.robot``).
    post_name : str
        The post writing the program (its ``NAME``).
    controller : str, optional
        The controller the post writes for, e.g. ``"KUKA KR C4"``; default the
        post's maker.

    Returns
    -------
    str
        E.g. "Written for a KUKA KR C4 controller, but the cell's robot is an ABB
        IRB 2400/10 (ABB_IRB2400). Chosen explicitly: that robot's controller
        takes abb_rapid."
        "" when the makers agree, or either is unknown (a user post, a robot not
        in the catalog).
    """
    maker, own = post_maker(post_name), robot_maker(robot)
    if maker is None or own is None or maker == own:
        return ""
    spec = catalog.get(robot)
    robot_text = " ".join(part for part in (spec.manufacturer, spec.model) if part) or robot
    controller = controller or maker
    own_post = ("takes %s" % spec.default_post if spec.default_post
                else "has no CadRobot post yet")
    return ("Written for %s %s controller, but the cell's robot is %s %s (%s). Chosen "
            "explicitly: that robot's controller %s." % (_article(controller), controller,
                                                         _article(robot_text), robot_text,
                                                         robot, own_post))


def _article(name):
    """"an" before a maker's name read with a vowel first (ABB, an IRC5), else "a"."""
    return "an" if name[:1].upper() in "AEIO" else "a"


# --- identifiers -------------------------------------------------------------

_IDENTIFIER = re.compile(r"[A-Za-z][A-Za-z0-9_]*")


def is_identifier(text, max_length, reserved):
    """Tell whether ``text`` is a letter-first identifier a post may declare.

    Parameters
    ----------
    text : str
    max_length : int
        The language's (or the post's) limit.
    reserved : iterable of str
        The language's reserved words; compared without regard to case.

    Returns
    -------
    bool
        True for 1 to ``max_length`` characters ``[A-Za-z][A-Za-z0-9_]*``
        that are not a reserved word.
    """
    return (bool(_IDENTIFIER.fullmatch(text)) and len(text) <= max_length
            and text.upper() not in {word.upper() for word in reserved})


class Namer:
    """Hands out valid identifiers, unique without regard to case.

    Parameters
    ----------
    reserved : iterable of str
        Names never given out (reserved words, predefined names), any case.
    max_length : int
        Longest identifier.
    separator : str, optional
        Put between the prefix and the text when a prefix is needed.
    """

    def __init__(self, reserved, max_length, separator=""):
        self._taken = {word.upper() for word in reserved}
        self._max_length = max_length
        self._separator = separator

    def add(self, text, prefix):
        """Return a fresh identifier made from ``text``.

        Parameters
        ----------
        text : str
            Wanted name; characters other than ``[A-Za-z0-9_]`` become
            ``_``.
        prefix : str
            Put in front (with the separator) when ``text`` does not start
            with a letter.

        Returns
        -------
        str
            At most ``max_length`` characters, starting with a letter;
            ``_2``, ``_3``, ... is appended when the name is taken.
        """
        base = re.sub(r"[^A-Za-z0-9_]", "_", str(text))
        if not base[:1].isascii() or not base[:1].isalpha():
            base = prefix + self._separator + base
        base = base[:self._max_length]
        name, number = base, 1
        while name.upper() in self._taken:
            number += 1
            suffix = f"_{number}"
            name = base[:self._max_length - len(suffix)] + suffix
        self._taken.add(name.upper())
        return name

    def is_taken(self, name):
        """True if ``name`` (any case) is reserved or already given out."""
        return name.upper() in self._taken


def target_names(program, namer, prefix):
    """Map each target name to (target, identifier), in execution order.

    A target used by several moves is named once.

    Parameters
    ----------
    program : CadRobotWB.core.program.Program
    namer : Namer
    prefix : str
        For target names that do not start with a letter.

    Returns
    -------
    dict of str to (Target, str)

    Raises
    ------
    PostError
        Two different poses under one target name (an error of the program
        generator).
    """
    out = {}
    for target in program.targets():
        if target.name in out:
            known = out[target.name][0]
            if known is not target and not np.allclose(known.T_b_t, target.T_b_t):
                raise PostError(f"Two different targets are both named '{target.name}' "
                                "in the program; regenerate the program.")
            continue
        out[target.name] = (target, namer.add(target.name, prefix))
    return out


def hash36(text, length):
    """``length`` upper-case base-36 characters of a SHA-1 of ``text``.

    Parameters
    ----------
    text : str
    length : int

    Returns
    -------
    str
    """
    number = int(hashlib.sha1(text.encode("utf-8")).hexdigest(), 16)
    digits = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ"
    out = ""
    for _ in range(length):
        number, rest = divmod(number, 36)
        out += digits[rest]
    return out


def upper_name(text, max_length, prefix, empty):
    """An upper-case program name made from any text.

    Parameters
    ----------
    text : str
    max_length : int
    prefix : str
        Put in front when the name does not start with a letter.
    empty : str
        The name of an empty text.

    Returns
    -------
    str
        ``A-Z``, ``0-9`` and ``_``, starting with a letter.  A longer name
        is cut to ``max_length - 3`` characters followed by three
        characters of a hash of the whole name (:func:`hash36`).
    """
    base = re.sub(r"[^A-Z0-9_]", "_", ascii_text(text).upper()) or empty
    if not base[0].isalpha():
        base = prefix + base
    if len(base) <= max_length:
        return base
    return base[:max_length - 3] + hash36(base, 3)


def is_upper_name(text, max_length):
    """True for 1 to ``max_length`` characters ``[A-Z][A-Z0-9_]*``.

    Parameters
    ----------
    text : str or None
    max_length : int

    Returns
    -------
    bool
    """
    return bool(re.fullmatch(r"[A-Z][A-Z0-9_]*", text or "")) and len(text) <= max_length


# --- checks ------------------------------------------------------------------


# --- file names --------------------------------------------------------------

def file_name(stem, extension):
    """The name of a file a post writes: ``file_stem(stem) + extension``.

    Every post builds its file names with this function.

    Parameters
    ----------
    stem : str
    extension : str
        With its dot, e.g. ``".mod"``.

    Returns
    -------
    str
    """
    return file_stem(stem) + extension


def check_file_stem(name, option):
    """Refuse a requested program name that cannot be a file name.

    For the languages whose program name is also its file's name.

    Parameters
    ----------
    name : str
        The value of option `option`.
    option : str

    Raises
    ------
    PostError
        `name` is not a valid file name everywhere (e.g. ``CON``).
    """
    if file_stem(name) != name:
        raise PostError(f"{option} {name!r} cannot be a file name on Windows (CON, PRN, AUX, NUL, "
                        f"COM1-9 and LPT1-9 are device names there); choose another {option}.")


def check_move(move, program, kinds, post, speed_decimals=None, speed_unit_mm_s=1.0,
               kinds_text=None):
    """Raise PostError when a move cannot be written.

    Parameters
    ----------
    move : CadRobotWB.core.program.Move
    program : CadRobotWB.core.program.Program
    kinds : iterable of str
        The move kinds the post writes.
    post : str
        The post's name in messages, e.g. ``"ABB RAPID"``.
    speed_decimals : int, optional
        The speed must not round to 0 at this many decimals of
        ``speed_unit_mm_s``; None: it must be greater than 0.
    speed_unit_mm_s : float, optional
        The unit the post writes speeds in (1000 for m/s).
    kinds_text : str, optional
        The kinds in the message; default ``", ".join(kinds)``.

    Raises
    ------
    PostError
        An unknown kind, a circular move without via point, an unknown work
        frame, a speed or zone out of range, or a pose that is not finite.
    """
    where = f"move to target '{move.target.name}'"
    if move.kind not in kinds:
        if kinds_text is None:
            kinds_text = ", ".join(kinds)
        raise PostError(f"The {where} is of kind '{move.kind}', which the {post} post cannot "
                        f"write (it writes {kinds_text} moves).")
    if move.kind == ir.CIRCULAR and move.via is None:
        raise PostError(f"The circular {where} has no via point; regenerate the program.")
    if move.frame not in program.frames:
        raise PostError(f"The {where} refers to work frame '{move.frame}', which the program "
                        "does not define.")
    speed = move.speed_mm_s
    if speed_decimals is None:
        if not np.isfinite(speed) or speed <= 0:
            raise PostError(f"The {where} has speed {speed} mm/s; set a speed > 0.")
    elif not np.isfinite(speed) or float(compact(speed / speed_unit_mm_s, speed_decimals)) <= 0:
        least = compact(10.0 ** -speed_decimals * speed_unit_mm_s, speed_decimals)
        raise PostError(f"The {where} has speed {speed} mm/s; set a speed of at least "
                        f"{least} mm/s.")
    if not np.isfinite(move.zone_mm) or move.zone_mm < 0:
        raise PostError(f"The {where} has zone {move.zone_mm} mm; set a zone of 0 (stop) "
                        "or more.")
    for target in (move.target, move.via):
        if target is not None and not np.all(np.isfinite(target.T_b_t)):
            raise PostError(f"Target '{target.name}' has a pose that is not a finite number; "
                            "check the path geometry.")


def check_tool_mass(tool):
    """Raise PostError unless the tool's mass is greater than 0.

    Parameters
    ----------
    tool : CadRobotWB.core.program.ToolData
    """
    if not tool.mass_kg > 0:
        raise PostError(f"Tool '{tool.name}' has mass {tool.mass_kg} kg; the controller needs "
                        "a mass greater than 0.")


def opw_robot_spec(program):
    """The catalog entry of the program's robot if it is an OPW robot or a chain arm.

    Arm configurations (confdata, S/T, CONFIG, RCONF) can be computed only
    for those (:mod:`..robots.motion.configuration_data`).

    Parameters
    ----------
    program : CadRobotWB.core.program.Program

    Returns
    -------
    catalog entry or None
        None for a robot not in the catalog, and for a UR arm.
    """
    try:
        spec = catalog.get(program.robot)
    except UnknownNameError:
        return None
    return spec if spec.opw is not None or chain_parameters(spec) is not None else None


# --- options -----------------------------------------------------------------


def whole_number(value, what, low, high):
    """An integer option within ``[low, high]``.

    Parameters
    ----------
    value : object
    what : str
        The option's name, for the message.
    low, high : int

    Returns
    -------
    int

    Raises
    ------
    PostError
        Not an integer (``bool`` is not one) or out of range.
    """
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) \
            or not low <= int(value) <= high:
        raise PostError(f"{what} must be a whole number from {low} to {high}, got {value!r}.")
    return int(value)


def positive_number(options, key, default):
    """A finite number option greater than 0 (``int`` or ``float``).

    Parameters
    ----------
    options : dict
    key : str
    default : float

    Returns
    -------
    float

    Raises
    ------
    PostError
    """
    value = options.get(key, default)
    if not (_is_number(value) and math.isfinite(value) and value > 0):
        raise PostError(f"{key} must be a number > 0, got {value!r}.")
    return float(value)


def _is_number(value):
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)


def bool_option(options, key, default):
    """A true/false option; any other value is refused.

    Parameters
    ----------
    options : dict
    key : str
    default : bool

    Returns
    -------
    bool

    Raises
    ------
    PostError
        The value is not ``True`` or ``False`` (``"maybe"``, ``1``, ``"yes"``):
        a typo must not switch a feature on.
    """
    value = options.get(key, default)
    if not isinstance(value, (bool, np.bool_)):
        raise PostError(f"{key} must be true or false, got {value!r}.")
    return bool(value)


def number_option(options, key, default, low=-math.inf, high=math.inf):
    """A finite number option within ``[low, high]``.

    Parameters
    ----------
    options : dict
    key : str
    default : float
    low, high : float, optional

    Returns
    -------
    float

    Raises
    ------
    PostError
        Not a number, not finite, or out of range.
    """
    value = options.get(key, default)
    if not (_is_number(value) and math.isfinite(value) and low <= value <= high):
        span = (f"from {compact(low)} to {compact(high)}" if math.isfinite(low) and math.isfinite(high)
                else f"of at least {compact(low)}" if math.isfinite(low)
                else f"of at most {compact(high)}" if math.isfinite(high) else "finite")
        raise PostError(f"{key} must be a number {span}, got {value!r}.")
    return float(value)


def whole_option(options, key, default, low, high):
    """An integer option within ``[low, high]``: :func:`whole_number` of ``options[key]``."""
    return whole_number(options.get(key, default), key, low, high)


def choice_option(options, key, default, choices):
    """An option that takes one of a few words.

    Parameters
    ----------
    options : dict
    key : str
    default : str
    choices : sequence of str

    Returns
    -------
    str

    Raises
    ------
    PostError
        Any other value; the message lists the choices.
    """
    value = options.get(key, default)
    if value not in choices:
        raise PostError(f"{key} must be one of {', '.join(map(str, choices))}, got {value!r}.")
    return value


def joint_targets_option(options):
    """The ``joint_targets`` option (default True), see :func:`is_joint_target_move`."""
    return bool_option(options, "joint_targets", True)


def is_joint_target_move(move, joint_targets):
    """True when `move` is written to a joint target rather than a Cartesian one.

    A joint move (approach and other air moves) whose target carries solved
    joints goes to those joints when the ``joint_targets`` option is on: the
    controller then cannot pick another arm configuration than the one
    CadRobot checked.

    Parameters
    ----------
    move : CadRobotWB.core.program.Move
    joint_targets : bool
        The option's value (:func:`joint_targets_option`).

    Returns
    -------
    bool
    """
    return bool(joint_targets) and move.kind == ir.JOINT and move.target.joints_deg is not None


def controller_joints_deg(program, target):
    """The joint values a controller is given for a target, degrees.

    Parameters
    ----------
    program : CadRobotWB.core.program.Program
    target : CadRobotWB.core.program.Target
        With ``joints_deg`` (model joints, filled by
        ``robots.motion.configuration.solve_program``).

    Returns
    -------
    ndarray, shape (6,)
        ``target.joints_deg`` in the controller's convention
        (:meth:`~CadRobotWB.robots.kinematics.models.RobotModel.controller_joints`: J3
        counted against the base on parallel-arm ABB and on FANUC arms).

    Raises
    ------
    PostError
        The target has no joints, or the program's robot is not in the
        catalog (its convention is unknown).
    """
    from ..robots.kinematics import models
    if target.joints_deg is None:
        raise PostError(f"Target '{target.name}' has no solved joints; check the program "
                        "with the robot first.")
    try:
        model = models.model(program.robot)
    except UnknownNameError:
        raise PostError(f"Robot '{program.robot}' is not in the catalog, so its joint "
                        "convention is unknown; set joint_targets=false.") from None
    return model.controller_joints(np.asarray(target.joints_deg, dtype=float))


def parts(items, size):
    """Consecutive slices of at most `size` items (a long program's parts).

    Parameters
    ----------
    items : sequence
    size : int
        At least 1.

    Returns
    -------
    list of list
        ``[items]`` when it is short enough; never an empty part.
    """
    items = list(items)
    return [items[i:i + size] for i in range(0, len(items), size)] or [[]]


def check_option_names(options, known, post):
    """Refuse an option the post does not have (a typo must not be ignored).

    Parameters
    ----------
    options : dict
    known : mapping or iterable of str
        The post's ``OPTIONS``; ``date`` is every post's.
    post : str
        The post's name, for the message.

    Raises
    ------
    PostError
        Names the unknown options and lists the known ones.
    """
    allowed = set(known) | {"date"}
    unknown = sorted(str(k) for k in options if k not in allowed)
    if unknown:
        raise PostError(f"The {post} post has no option {', '.join(unknown)}; its options are "
                        f"{', '.join(sorted(allowed))}."
                        + command_line.outside_gui(" `%s` describes them.", "posts"))


def date_option(options, default):
    """The ``"date"`` option: a ``datetime.datetime``.

    Parameters
    ----------
    options : dict
    default : datetime.datetime

    Returns
    -------
    datetime.datetime

    Raises
    ------
    PostError
    """
    date = options.get("date", default)
    if not isinstance(date, datetime.datetime):
        raise PostError(f"date must be a datetime.datetime, got {date!r}.")
    return date


def frame_numbers(program, user_frame, low, high, what="user_frame", overflow=None):
    """The user frame number of each work frame of a program.

    Parameters
    ----------
    program : CadRobotWB.core.program.Program
    user_frame : int or dict of str to int
        The number of the first frame (the next frames, in
        ``program.frames`` order, take the next numbers), or one number per
        frame name.
    low, high : int
        The controller's range.
    what : str, optional
        The option's name, for error messages.
    overflow : str, optional
        Message when the frames run past ``high``; a format string with
        ``{count}``, ``{first}``, ``{last}`` and ``{high}``.

    Returns
    -------
    dict of str to int

    Raises
    ------
    PostError
        A number out of range, a frame without a number, or two frames with
        one number.
    """
    names = list(program.frames)
    if isinstance(user_frame, dict):
        missing = [n for n in names if n not in user_frame]
        if missing:
            raise PostError(f"Option {what} gives no number for work frame(s) "
                            f"{', '.join(missing)}.")
        numbers = {n: whole_number(user_frame[n], f"{what}[{n!r}]", low, high) for n in names}
    else:
        first = whole_number(user_frame, what, low, high)
        last = first + len(names) - 1
        if last > high and overflow is not None:
            raise PostError(overflow.format(count=len(names), first=first, last=last,
                                            high=high))
        if last > high:
            raise PostError(f"{len(names)} work frames need {what} numbers {first} to {last}, "
                            f"beyond {high}; pass a smaller {what} or a dict.")
        numbers = {n: first + i for i, n in enumerate(names)}
    if len(set(numbers.values())) != len(numbers):
        raise PostError(f"Option {what} gives two work frames the same number: {numbers}.")
    return numbers


def xyz_fixed_angles(T, angle_decimals):
    """X, Y, Z (mm, 3 decimals) and fixed-axis angles about X, Y, Z (deg).

    Parameters
    ----------
    T : array_like, shape (4, 4)
    angle_decimals : int

    Returns
    -------
    list of 6 str
        ``R = Rz(c) Ry(b) Rx(a)``; a, c in (-180, 180], b in [-90, 90];
        no ``-0.000``.
    """
    T = np.asarray(T, dtype=float)
    angles = np.degrees(rotations.euler_xyz_fixed_from_matrix(T[:3, :3]))
    return [fixed(v, 3) for v in T[:3, 3]] + [fixed(a, angle_decimals) for a in angles]


# ---- welds ------------------------------------------------------------------
# Helpers of the weld branches of the posts (issue 22). A weld run's start move
# (``moves[run.start]``) ends where the arc strikes; the moves ``start + 1 ..
# end`` weld; the arc goes out at the target of ``moves[run.end]``.

def check_weld_runs(program, post, tracking=("none",)):
    """Refuse a program whose weld runs a post cannot write as arc-on stretches.

    Parameters
    ----------
    program : Program
    post : str
        The controller's name, for the message.
    tracking : tuple of str
        The tracking sensors (``Tracking.sensor``) the post writes.

    Raises
    ------
    PostError
        A run breaking a rule of WeldRun (:func:`checked_weld_runs`), or asking
        for another tracking sensor.
    """
    list(checked_weld_runs(program))
    for _, run in program.weld_runs():
        if run.tracking.sensor not in tracking:
            raise PostError(f"Weld {run.name!r} ({run.label}) asks for {run.tracking.sensor} "
                            f"seam tracking, which {post} cannot write: set its tracking to "
                            f"{' or '.join(tracking)}.")


def weld_run_starting(path, index):
    """The WeldRun of `path` whose arc strikes at the target of move `index`, or None."""
    return next((run for run in path.welds if run.start == index), None)


def weld_run_ending(path, index):
    """The WeldRun of `path` whose arc goes out at the target of move `index`, or None.

    Where two welds touch, one move ends the first and starts the second:
    write the first's arc-off instructions, then the second's arc-on.
    """
    return next((run for run in path.welds if run.end == index), None)


def schedule_comment_lines(run):
    """Plain-text lines stating a run's schedule for the controller's screens.

    Returns
    -------
    list of str
        Name and source, current, voltage, wire feed, travel speed, gas
        pre-/post-flow, crater and burn-back, CTWD; numbers in the units the
        lines name.
    """
    s = run.schedule
    current = "" if s.current_a is None else f"{compact(s.current_a, 1)} A, "
    crater_a = "" if s.crater_current_a is None else f"{compact(s.crater_current_a, 1)} A, "
    estimated = " (estimated)" if s.wire_feed_estimated else ""
    lines = [f"Schedule {s.name}, wire {compact(s.wire_mm, 2)} mm {s.process} {s.gas}",
             f"Weld: {current}{compact(s.voltage_v, 1)} V, wire feed "
             f"{compact(s.wire_feed_m_min, 1)} m/min{estimated}",
             f"Travel speed {compact(s.travel_speed_mm_s, 2)} mm/s",
             f"Gas pre-flow {compact(s.gas_preflow_s, 2)} s, post-flow "
             f"{compact(s.gas_postflow_s, 2)} s",
             f"Crater: {crater_a}{compact(s.crater_voltage_v, 1)} V, wire feed "
             f"{compact(s.crater_wire_feed_m_min, 1)} m/min, {compact(s.crater_fill_s, 2)} s",
             f"Burn-back {compact(s.burnback_s, 3)} s, CTWD {compact(s.ctwd_mm, 1)} mm"]
    if s.source:
        lines.append(f"Source: {s.source}")
    return lines


def weave_pattern_for(post, run, table):
    """The controller's name of a run's weave pattern.

    Parameters
    ----------
    post : str
        The controller's name, for the message.
    run : WeldRun
        With a weave.
    table : dict of str to str or None
        Pattern -> the controller's name; None or missing: not written.

    Raises
    ------
    PostError
        The pattern is not in `table`; the message names the patterns that are.
    """
    name = table.get(run.weave.pattern)
    if name is None:
        usable = ", ".join(p for p, n in table.items() if n is not None)
        raise PostError(f"Weld {run.name!r} ({run.label}): {post} has no "
                        f"{run.weave.pattern} weave here: use {usable}.")
    return name


# -- welds, for the ABB and KUKA posts (postsak) --
# A move's step in a weld run: "start" (the arc strikes at its target), "weld"
# (the arc burns along it), "end" (the last welded move: the arc goes out at its
# target). The runs are checked by core/weld_runs.check_runs.

WELD_START, WELD_ON, WELD_END = "start", "weld", "end"


def weld_what(path, run):
    """``Weld 'label' (run name) of path 'label'``, for messages."""
    part = f", part {run.part}" if run.part > 1 else ""
    return (f"Weld '{comment_text(run.label) or run.name}' (run {run.name}{part}) of path "
            f"'{path_label(path)}'")


def weld_steps(path):
    """What each move of a path does with the arc.

    Returns
    -------
    list of (tuple or None, list of WeldRun)
        One per move: the move's own arc step ``(role, run)`` --
        (:data:`WELD_START`, run) for a run that starts on a linear move,
        (:data:`WELD_ON`, run) for a welded move, (:data:`WELD_END`, run) for
        the last one -- or None for a move without arc; then the runs whose arc
        strikes at the move's target after it is reached (a run that starts on
        a circular move, or where the run before it ended): the post writes a
        linear arc start to that same point.
    """
    steps = [(None, []) for _ in path.moves]
    for run in path.welds:
        own, after = steps[run.start]
        if own is None and path.moves[run.start].kind == ir.LINEAR:
            steps[run.start] = ((WELD_START, run), after)
        else:
            after.append(run)
        for index in range(run.start + 1, run.end):
            steps[index] = ((WELD_ON, run), steps[index][1])
        steps[run.end] = ((WELD_END, run), steps[run.end][1])
    return steps


def weld_spans(path):
    """``[run, start, end]`` of each stretch of moves a split must keep whole: a weld
    run's moves ``start .. end``, runs that meet at a move joined (``run`` the first)."""
    spans = []
    for run in path.welds:
        if spans and run.start <= spans[-1][2]:
            spans[-1][2] = run.end
        else:
            spans.append([run, run.start, run.end])
    return spans


def dwell_lengths_mm(run):
    """(left, centre, right) dwells of the run's weave as travel along the seam, mm
    (dwell time x travel speed); the centre dwell is the one at each crossing
    (half the weave's ``dwell_center_s``)."""
    speed = run.schedule.travel_speed_mm_s
    weave = run.weave
    return (weave.dwell_left_s * speed, weave.dwell_center_s / 2 * speed,
            weave.dwell_right_s * speed)


def run_comment_lines(run, width=70):
    """A run in words for a program header: which weld, its schedule
    (:func:`schedule_comment_lines`), its weave and its tracking.

    Parameters
    ----------
    run : WeldRun
    width : int, optional
        Longest line; longer ones are wrapped (indented).

    Returns
    -------
    list of str
        Lines without comment marks.
    """
    lines = schedule_comment_lines(run)
    if run.weave is not None:
        w, speed = run.weave, run.schedule.travel_speed_mm_s
        lines += [f"Weave {w.pattern} {compact(w.width_mm, 2)} mm wide, "
                  f"{compact(w.cycle_length_mm(speed), 3)} mm per cycle "
                  f"({compact(w.frequency(speed), 3)} Hz)",
                  f"Dwells left/centre/right {compact(w.dwell_left_s, 3)}/"
                  f"{compact(w.dwell_center_s, 3)}/{compact(w.dwell_right_s, 3)} s, angle "
                  f"{compact(w.angle_deg, 2)} deg"]
    else:
        lines.append("No weave")
    lines.append(f"Tracking: {run.tracking.sensor}")
    out = textwrap.wrap(f"Weld {comment_text(run.label) or run.name} (run {run.name}, segments "
                        f"{run.first_segment}-{run.last_segment}, part {run.part}):", width,
                        subsequent_indent="    ")
    for line in lines:
        out += textwrap.wrap(comment_text(line), width, initial_indent="  ",
                             subsequent_indent="    ")
    return out


def checked_weld_runs(program):
    """``(path, run, what)`` of every weld run (``what``: :func:`weld_what`), after
    ``core.weld_runs.check_runs`` of the whole program.

    Raises
    ------
    PostError
        check_runs' one-line message: a run breaking a rule of WeldRun (indices,
        fine ignition and crater moves, welded moves linear or circular at the
        travel speed, ...).
    """
    try:
        weld_runs.check_runs(program)
    except InputError as error:
        raise PostError(str(error)) from None
    for path, run in program.weld_runs():
        yield path, run, weld_what(path, run)


def check_weld_basics(path, run, post, patterns, words):
    """The refusals every weld post shares.

    Parameters
    ----------
    path : ProgramPath
    run : WeldRun
    post : str
        The controller in messages, e.g. ``"KUKA ArcTech"``.
    patterns : dict
        Weave patterns the post writes (:func:`weave_pattern_for`).
    words : dict
        ``"start"``: the arc-start instruction; ``"arc"``, ``"laser"``: what the
        controller calls through-arc and laser tracking.

    Raises
    ------
    PostError
        A run that starts on a joint move, a weave pattern the post lacks, laser tracking, through-arc tracking without a weave.
    """
    what = weld_what(path, run)
    start = path.moves[run.start]
    if start.kind == ir.JOINT:
        raise PostError(f"{what} starts on a joint move to '{start.target.name}': "
                        f"{words['start']} ignites on a linear move; start the weld with a "
                        "straight entry.")
    if run.weave is not None:
        weave_pattern_for(post, run, patterns)
    if run.tracking.sensor == "laser":
        raise PostError(f"{what} tracks with the laser ({words['laser']}), which the {post} "
                        "post does not write with the arc: set its tracking to none or arc.")
    if run.tracking.sensor == "arc" and run.weave is None:
        raise PostError(f"{what}: through-arc tracking ({words['arc']}) needs a weave: give "
                        "the weld a weave or set its tracking to none.")


# ---- external axes (issue 23: the ABB and KUKA posts) -------------------------
# ``program.external`` (core.mechanisms.ExternalAxes) and each ``Target.external``
# (track mm, then positioner deg). The controller's world frame is taken as the
# robot base with the track at 0 (its calibration position); without a track it
# is the robot base, as the posts assume for programs without external axes.

def external_values(program, max_axes, post):
    """Every target's external-axis values, checked.

    Parameters
    ----------
    program : Program
        With ``program.external`` set.
    max_axes : int
        Most external axes the language carries in a position.
    post : str
        The post's name for messages, e.g. ``"ABB RAPID"``.

    Returns
    -------
    dict of str to ndarray, shape (K,)
        By target name; a target without values (``Target.external`` None)
        takes the mechanisms' drawn values, as the plan's "None = as drawn".

    Raises
    ------
    PostError
        Too many axes, or a target whose values are not K finite numbers.
    """
    external = program.external
    axes = external.axes()
    if len(axes) > max_axes:
        raise PostError(f"Program '{program.name}': {post} carries at most {max_axes} external "
                        f"axes and the cell's mechanisms have {len(axes)}: remove a mechanism.")
    drawn = external.drawn_at()
    out = {}
    for target in program.targets():
        values = drawn if target.external is None else np.asarray(target.external, dtype=float)
        if values.shape != (len(axes),) or not np.all(np.isfinite(values)):
            raise PostError(f"Target '{target.name}' has external-axis values "
                            f"{np.asarray(target.external).tolist()} that are not {len(axes)} "
                            "finite numbers (track mm, then positioner deg): choose the "
                            "external axes again.")
        out[target.name] = values
    return out


def external_texts(program, values, mm_decimals, deg_decimals):
    """The values of one target as text, in program order.

    Parameters
    ----------
    program : Program
    values : array_like, shape (K,)
    mm_decimals, deg_decimals : int
        Decimals of linear (mm) and rotary (deg) axes.

    Returns
    -------
    list of str
    """
    return [fixed(v, mm_decimals if axis.unit == "mm" else deg_decimals)
            for (_, axis), v in zip(program.external.axes(), values)]


def is_moving_frame(program, key):
    """True if work frame `key` rides on the program's positioner."""
    external = program.external
    return (external is not None and external.positioner is not None
            and key in external.moving_frames)


def T_world_u(external):
    """The controller's world frame in {U}: the robot base with the track at 0.

    Parameters
    ----------
    external : core.mechanisms.ExternalAxes

    Returns
    -------
    ndarray, shape (4, 4)
    """
    values = external.drawn_at().copy()
    if external.track is not None:
        values[:len(external.track.axes)] = 0.0
    return external.T_u_r_at(values)


def frame_for_controller(program, key):
    """What the controller's frame of work frame `key` holds, shape (4, 4), mm.

    A frame on the positioner: the frame in the positioner's flange {P}
    (:meth:`ExternalAxes.T_p_b`), which the positioner carries; a fixed frame
    in a cell with a track: the frame in the world (:func:`T_world_u`); else
    ``WorkFrame.T_r_b``.
    """
    frame = program.frames[key]
    external = program.external
    if is_moving_frame(program, key):
        return external.T_p_b(frame)
    if external is not None and external.track is not None:
        return in_world(external, frame.T_u_b)
    return np.asarray(frame.T_r_b, dtype=float)


def in_world(external, T_u_x):
    """A frame given in {U} in the controller's world frame (:func:`T_world_u`),
    shape (4, 4), mm."""
    return frames.invert_transform(T_world_u(external)) @ np.asarray(T_u_x, dtype=float)


def external_axis_lines(program, names):
    """One comment line per external axis: ``"<name> = <label> <axis> (<unit>)"``.

    Parameters
    ----------
    program : Program
    names : list of str
        The language's name of each axis in program order (``eax_a``, ``E1``).
    """
    return [f"{name} = {comment_text(mechanism.label)} {axis.name} ({axis.unit})"
            for name, (mechanism, axis) in zip(names, program.external.axes())]


# --- external axes of the FANUC, Yaskawa and UR posts (issue 23) --------------


def target_external_values(program, target):
    """The external axis values of a target, in ``ExternalAxes`` order.

    Parameters
    ----------
    program : Program
        With ``program.external`` set.
    target : Target

    Returns
    -------
    ndarray, shape (K,)
        ``target.external`` (track mm, then positioner deg), or every axis
        at its drawn value where the chooser left it None.

    Raises
    ------
    PostError
        The target holds another number of values than the cell has axes.
    """
    external = program.external
    if target.external is None:
        return external.drawn_at()
    values = np.asarray(target.external, dtype=float).reshape(-1)
    count = len(external.axes())
    if len(values) != count or not np.all(np.isfinite(values)):
        raise PostError(f"Target '{target.name}' holds {len(values)} external axis values, the "
                        f"cell has {count} finite ones ({', '.join(external.axis_names())}); "
                        "generate the program again.")
    return values


def pose_in_drawn_frame(program, frame_name, target):
    """A target's TCP in its work frame as the document draws it, at the
    target's external axis values.

    The work frame {B} drawn (every mechanism at ``drawn_at``) stands still in
    the cell: it is the user frame a controller with coordinated external
    axes is taught with.  A frame riding on the positioner moves with it to
    ``motion(v) @ T_u_b``, so the TCP, fixed in the moving frame, is at
    ``inv(T_u_b) @ motion(v) @ T_u_b @ T_b_t`` in the drawn one.  A track
    moves the robot, not the frame: it changes nothing here.

    Parameters
    ----------
    program : Program
    frame_name : str
    target : Target

    Returns
    -------
    T_b0_t : ndarray, shape (4, 4)
        mm; ``target.T_b_t`` itself without external axes.
    """
    external = program.external
    T_b_t = np.asarray(target.T_b_t, dtype=float)
    if external is None or external.positioner is None or \
            frame_name not in external.moving_frames:
        return T_b_t
    _, turned = external.split(target_external_values(program, target))
    T_u_b = np.asarray(program.frames[frame_name].T_u_b, dtype=float)
    return np.linalg.inv(T_u_b) @ external.positioner.motion(turned) @ T_u_b @ T_b_t


def is_coordinated_move(move):
    """True for a linear or circular move along the path (welding or not):
    the moves a positioner's coordinated motion (FANUC ``COORD``, Yaskawa
    ``SMOVL``/``SMOVC``) applies to; approach, entry and retract move in the
    air with the positioner still."""
    return move.kind != ir.JOINT and move.role not in (
        ir.ROLE_APPROACH, ir.ROLE_ENTRY, ir.ROLE_RETRACT)


def external_axes_comments(program, wrap):
    """Comment lines naming each external axis of a program (``E2 = Positioner
    tilt (deg)``) and the values the document draws the mechanisms at.

    Parameters
    ----------
    program : Program
        With ``program.external`` set.
    wrap : callable
        ``wrap(text) -> list of str``: the post's comment lines of a text.

    Returns
    -------
    list of str
    """
    external = program.external
    lines = [f"{name} = {comment_text(mechanism.label)} {axis.name} ({axis.unit})"
             for name, (mechanism, axis) in zip(external.axis_names(), external.axes())]
    drawn = ", ".join(f"{name}={compact(value, 3)}" for name, value in
                      zip(external.axis_names(), external.drawn_at()))
    return ["External axes:"] + [out for line in lines + [f"Drawn at {drawn}"]
                                 for out in wrap(line)]
