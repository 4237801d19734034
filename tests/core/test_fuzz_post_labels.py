"""Fuzzing the built-in posts with the user's labels (posts/): any text gives valid names.

The labels a user types in FreeCAD reach a program as the cell's name (the
program and its files), the tool's, the calibration frames', the paths' names
and labels, the move comments and the source note. The property: whatever
those texts are (any unicode, NUL, lone surrogates, quotes, line breaks, very
long, a reserved word of each language, a name starting with a digit, two
labels that differ only where the language cannot tell them apart), each of
the five built-in posts

* writes file names of letters, digits and ``_`` with the post's extension,
  distinct without regard to case;
* writes only printable ASCII text (line breaks and tabs aside), so no label
  breaks a comment or a string out of its line;
* declares only names its language accepts (the post's own ``is_name`` test,
  which states the language's rule: letters first, length, not a reserved
  word), distinct without regard to case within each file.

RAPID output of the seed examples also passes rapidchecker (tests/rapid_check.py).
"""

import dataclasses
import re

import pytest

import fuzzing

fuzzing.require()

from hypothesis import assume, example, given, strategies as st  # noqa: E402

import post_programs  # noqa: E402
from CadRobotWB import posts  # noqa: E402
from CadRobotWB.posts import abb_rapid, fanuc_ls, kuka_krl, motoman_inform, ur_script  # noqa: E402
from rapid_check import needs_rapidchecker, rapid_errors  # noqa: E402

#: Where labels go: the cell (program) name, the tool, the two frames, the two paths'
#: names and labels, the comments and the source note.
SLOTS = ("cell", "tool", "frame_a", "frame_b", "path_a", "path_b", "comment", "source")

#: Names each post declares: regular expressions whose group 1 is a declared name.
DECLARATIONS = {
    "abb_rapid": [r"^\s*MODULE\s+(\S+)", r"^\s*(?:LOCAL\s+)?PROC\s+([^\s(]+)\(",
                  r"^\s*(?:LOCAL\s+)?(?:PERS|CONST|VAR)\s+\w+\s+([^\s:;]+)\s*(?::=|;)"],
    "kuka_krl": [r"^\s*(?:GLOBAL\s+)?DEF\s+([^\s(]+)\s*\(", r"^\s*DEFDAT\s+(\S+)",
                 r"^\s*DECL\s+(?:GLOBAL\s+)?\w+\s+([^\s=]+)\s*="],
    "ur_script": [r"^\s*def\s+([^\s(]+)\(", r"^\s*([^\s=#]+)\s*=\s*p\["],
    "fanuc_ls": [r"^/PROG\s+(\S+)", r"^\s*\d+:\s*CALL\s+([^\s;]+)"],
    "motoman_inform": [r"^//NAME\s+(\S+)", r"^CALL\s+JOB:(\S+)"],
}

#: Each post's test of a name it may declare.
IS_NAME = {
    "abb_rapid": abb_rapid.is_identifier,
    "kuka_krl": kuka_krl.is_name,
    "ur_script": ur_script.is_name,
    "fanuc_ls": lambda text: fanuc_ls.is_program_name(text, fanuc_ls.MAX_NAME_LENGTH),
    "motoman_inform": lambda text: motoman_inform.is_job_name(text, 32),
}

#: Names a label must not become as it is: every post's reserved words, plus names
#: the languages predefine, in the cases a user may type them.
RESERVED = sorted(abb_rapid.RESERVED_WORDS | kuka_krl.RESERVED_WORDS | ur_script.RESERVED_WORDS
                  | {"main", "tool0", "wobj0", "fine", "vmax", "$BASE", "$TOOL", "PROG", "JOB"})

#: Hostile texts of issue 21's classes.
HOSTILE = ["", " ", "\x00", "a\x00b", "\ud800", "x\udfffy", '"', "'", "\"; ENDPROC", "\\", "\n",
           "a\r\nMoveL p1", "\t", "\u00e9t\u00e9", "\u0661\u0662", "\u202e", "\U0001f600", "1abc",
           "9", "_x", "-", ".", "..", "CON", "x" * 300, "\u00df" * 40, "%s", "{}", "$BASE", "&ACCESS",
           "; comment", "# comment", "! comment", "//NAME X", "/PROG X", "'", "Cell", "cell", "CELL"]

labels = st.one_of(st.sampled_from(HOSTILE), st.sampled_from(RESERVED),
                   st.text(max_size=40),
                   st.text(alphabet=st.characters(max_codepoint=127), max_size=60))


def labelled_program(texts):
    """The posts' shared two-frame program with the labels of `texts` (slot -> text)."""
    program = post_programs.two_frame_program("ABB_IRB2400")
    keys = {"Table": texts["frame_a"], "Fixture": texts["frame_b"]}
    frames = {keys[key]: dataclasses.replace(frame, name=keys[key], source=texts["source"])
              for key, frame in program.frames.items()}
    paths = [dataclasses.replace(
        path, name=texts[slot], label=texts[slot],
        moves=[dataclasses.replace(move, frame=keys[move.frame], comment=texts["comment"])
               for move in path.moves])
        for path, slot in zip(program.paths, ("path_a", "path_b"))]
    tool = dataclasses.replace(program.tool, name=texts["tool"], label=texts["tool"])
    return dataclasses.replace(program, name=texts["cell"], tool=tool, frames=frames,
                               paths=paths, source=texts["source"])


def declared_names(post, text):
    """Every name the file `text` of `post` declares, in order."""
    return [match.group(1) for line in text.splitlines() for pattern in DECLARATIONS[post]
            for match in [re.search(pattern, line)] if match]


def assert_valid_program(post, files):
    """The three promises of the module docstring for one post's files."""
    module = posts.get(post)
    stems = [name.rpartition(".")[0] for name, _ in files]
    for name, _ in files:
        stem, _, extension = name.rpartition(".")
        assert re.fullmatch(r"[A-Za-z0-9_]+", stem), name
        assert extension.lower() in [e.lstrip(".").lower() for e in module.FILE_EXTENSIONS], name
    assert len({name.upper() for name, _ in files}) == len(files), stems
    for name, text in files:
        bad = sorted({c for c in text if not (" " <= c <= "~" or c in "\n\r\t")})
        assert not bad, (name, bad)
        names = declared_names(post, text)
        assert names, (name, text[:300])
        invalid = [n for n in names if not IS_NAME[post](n)]
        assert not invalid, (name, invalid)
        assert len({n.upper() for n in names}) == len(names), (name, names)


def export_all(texts):
    """post name -> its files for the program labelled with `texts`."""
    program = labelled_program(texts)
    return {post: posts.get(post).export(program, {}) for post in sorted(DECLARATIONS)}


def texts_of(*values):
    return dict(zip(SLOTS, values))


#: Seeds: one per class of issue 21 (the same text everywhere, or the frames colliding).
SEEDS = [
    texts_of("\x00", "a\x00b", "\ud800", "x\udfffy", "\x00", "\ud800", "\x00\ud800", "\ud800"),
    texts_of('"', "'", "\"; ENDPROC", "\\", "\n", "a\r\nMoveL p1", '"\n!', "\"\r\n"),
    texts_of("x" * 300, "y" * 300, "z" * 300 + "1", "z" * 300 + "2", "w" * 300, "w" * 299,
             "c" * 500, "s" * 500),
    texts_of("MODULE", "PROC", "tool0", "wobj0", "main", "ENDPROC", "MoveL", "fine"),
    texts_of("DEF", "END", "$BASE", "$TOOL", "DECL", "E6POS", "&ACCESS", "; x"),
    texts_of("def", "end", "p", "pose_trans", "movel", "movej", "# x", "global"),
    texts_of("PROG", "CALL", "P", "PR", "UFRAME", "UTOOL", "! x", "/PROG X"),
    texts_of("JOB", "NOP", "END", "MOVL", "USER", "TOOL", "' x", "//NAME X"),
    texts_of("1cell", "2", "3a", "4b", "5", "6", "7", "8"),
    texts_of("\u00e9t\u00e9", "\u00c9T\u00c9", "caf\u00e9", "cafe", "\U0001f600", "\U0001f601",
             "\u202e", "\u0661"),
    texts_of("", " ", "", " ", "", "", "", ""),
    texts_of("Cell", "cell", "CELL", "cell_", "Table", "table", "", ""),
    texts_of("a-b", "a_b", "a b", "a.b", "a/b", "a\\b", "", ""),
]


@given(texts=st.fixed_dictionaries({slot: labels for slot in SLOTS}))
@fuzzing.examples(60)
def test_any_labels_give_valid_unique_names_in_every_post(texts):
    assume(texts["frame_a"] != texts["frame_b"])
    for post, files in export_all(texts).items():
        assert_valid_program(post, files)


for seed in SEEDS:
    test_any_labels_give_valid_unique_names_in_every_post = example(texts=seed)(
        test_any_labels_give_valid_unique_names_in_every_post)


@needs_rapidchecker
@pytest.mark.parametrize("texts", [SEEDS[0], SEEDS[1], SEEDS[3]],
                         ids=["nul-surrogates", "quotes-newlines", "rapid-reserved"])
def test_rapid_of_hostile_labels_passes_rapidchecker(texts):
    for name, text in export_all(texts)["abb_rapid"]:
        assert rapid_errors(text) == [], (name, rapid_errors(text))


@pytest.mark.parametrize("post", sorted(DECLARATIONS))
def test_control_characters_of_a_label_become_question_marks_in_comments(post):
    """NUL, BEL, ESC and DEL in the path label: '?' in the comment, never the byte itself."""
    texts = dict(zip(SLOTS, ["Cell", "Torch", "Table", "Fixture", "Seam", "Contour",
                             "weld", "doc"]))
    texts["path_a"] = "Seam\x00one\x07two\x1bthree\x7f"
    text = "".join(text for _, text in export_all(texts)[post])
    assert "Seam?one?two?three?" in text, post
    assert not re.search("[\x00-\x08\x0b\x0c\x0e-\x1f\x7f]", text), post
