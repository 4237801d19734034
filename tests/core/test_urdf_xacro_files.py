"""A xacro file is expanded only when it reads inside its own folder and package
(robots/urdf/xacro_files.py).

Layout: tmp/pkg/package.xml, tmp/pkg/urdf/arm.xacro (the file under test),
tmp/pkg/urdf/parts/*.xacro (includes it may read), tmp/outside/secret.xacro
(must never be read).  Each refusal is one line naming the file and the
reference, raised before xacro (or its absence) is looked at.
"""

import os

import pytest

from CadRobotWB.errors import CadRobotError
from CadRobotWB.robots.urdf import from_urdf, xacro_files

XACRO = '<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">%s</robot>'


def include(filename):
    return '<xacro:include filename="%s"/>' % filename


@pytest.fixture
def package(tmp_path):
    (tmp_path / "pkg" / "urdf" / "parts").mkdir(parents=True)
    (tmp_path / "pkg" / "package.xml").write_text("<package/>")
    (tmp_path / "pkg" / "urdf" / "parts" / "wrist.xacro").write_text(XACRO % "")
    (tmp_path / "pkg" / "common.xacro").write_text(XACRO % "")
    (tmp_path / "outside").mkdir()
    (tmp_path / "outside" / "secret.xacro").write_text(XACRO % "")
    return tmp_path / "pkg" / "urdf"


@pytest.mark.parametrize("body, words", [
    (include("../../outside/secret.xacro"), "'../../outside/secret.xacro' leaves"),
    (include("/etc/passwd"), "'/etc/passwd' is not a plain relative path"),
    (include("file:///etc/passwd"), "is not a plain relative path"),
    (include("$(find other_pkg)/urdf/x.xacro"), "'$(find' reads from outside"),
    (include("${prefix}wrist.xacro"), "'${prefix}wrist.xacro' is not a plain relative path"),
    (include("$(arg path)"), "is not a plain relative path"),
    ('<xacro:property name="h" value="$(env HOME)"/>', "'$(env' reads from outside"),
    ('<xacro:property name="h" value="$(optenv HOME)"/>', "'$(optenv' reads"),
    ('<xacro:property name="c" value="${xacro.load_yaml(\'c.yaml\')}"/>', "'load_yaml' reads"),
    ('<xacro:property name="e" value="$(eval 1)"/>', "'$(eval' reads"),
    (include("parts/link_out.xacro"), "leaves the file's folder and package"),   # a symlink out
    (include("parts/nested.xacro"), "'../../../outside/secret.xacro' leaves"),   # one level down
    (include(""), "'' is not a plain relative path"),
])
def test_a_xacro_read_outside_is_refused_naming_file_and_reference(package, body, words):
    os.symlink(str(package.parent.parent / "outside" / "secret.xacro"),
               str(package / "parts" / "link_out.xacro"))
    (package / "parts" / "nested.xacro").write_text(XACRO % include("../../../outside/secret.xacro"))
    top = package / "arm.xacro"
    top.write_text(XACRO % body)
    with pytest.raises(xacro_files.XacroPathError) as error:
        from_urdf.read_description(str(top))
    message = str(error.value)
    assert message.startswith("xacro file '%s" % package) and words in message
    assert "\n" not in message


def test_includes_inside_the_folder_and_package_are_read_once_and_bounded(package, monkeypatch):
    top = package / "arm.xacro"
    top.write_text(XACRO % (include("parts/wrist.xacro") + include("../common.xacro")
                            + include("parts/wrist.xacro")))
    assert xacro_files.check_includes(str(top)) == [
        os.path.realpath(str(p)) for p in (top, package / "parts" / "wrist.xacro",
                                           package.parent / "common.xacro")]
    monkeypatch.setattr(xacro_files, "MAX_FILES", 2)
    with pytest.raises(CadRobotError, match="includes more than 2 files"):
        xacro_files.check_includes(str(top))


def test_an_include_cycle_ends(package):
    (package / "a.xacro").write_text(XACRO % include("b.xacro"))
    (package / "b.xacro").write_text(XACRO % include("a.xacro"))
    assert len(xacro_files.check_includes(str(package / "a.xacro"))) == 2
