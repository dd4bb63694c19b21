#!/usr/bin/env python3
"""Writes docs/bad-input.md: every malformed-input case the test suite checks, run through
the built binary build/epsray, with the exit code and the one line it prints on stderr.

The cases are copied from tests/test_scene.cpp (BadScene, BadPath and the file tests),
tests/test_cli.cpp (CliBadScene, CliBadFlags and the single bad-scene tests) and
tests/test_viewer.cpp (ViewerScript.BadLinesNameTheLine and the ViewerCli tests). Each one
runs in a fresh temporary folder holding only its input files; the script also checks that
the run exits 2, prints exactly one line, names `file:line:` for file inputs, says what the
test expects it to say, and writes nothing. It never builds anything.

    python3 tools/bad-input-table.py            # runs every case, rewrites docs/bad-input.md
    python3 tools/bad-input-table.py --check    # runs every case, writes nothing, exit 1 on a surprise
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BINARY = ROOT / "build" / "epsray"
DOC = ROOT / "docs" / "bad-input.md"
VIEW_SCENE = ROOT / "scenes" / "tests" / "sphere.nff"

CATEGORIES = ["scene syntax", "numbers", "geometry", "textures", "camera paths", "flags and outputs",
              "viewer scripts"]


class Case:
    """One malformed input: files written into the temporary folder, then `args` run there."""

    def __init__(self, category, name, files, args, shown, line=None, phrase="", file_input=True,
                 display=None):
        assert category in CATEGORIES, category
        self.category = category
        self.name = name            # the test's name for the case
        self.files = files          # {file name: bytes}
        self.args = args            # build/epsray's arguments
        self.shown = shown          # the input column: the offending line(s) or the flag
        self.line = line            # the line the test expects (None: the test pins none)
        self.phrase = phrase        # what the test expects the message to contain
        self.file_input = file_input  # the bad thing is in a file: the message must say file:line:
        self.display = display      # DISPLAY for the run (None: unset)


CASES = []


def add(*a, **k):
    CASES.append(Case(*a, **k))


# --- scene text, as in tests/test_scene.cpp -------------------------------------------------

VIEW7 = b"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 16 12\n"


def show_lines(text):
    """Lines joined by ' ⏎ ', bytes outside printable ASCII as \\xNN, CR as \\r."""
    out = []
    for ch in text:
        if ch == 0x0A:
            out.append(" ⏎ ")
        elif ch == 0x0D:
            out.append("\\r")
        elif ch == 0x09:
            out.append("\\t")
        elif 0x20 <= ch < 0x7F:
            out.append(chr(ch))
        else:
            out.append("\\x%02x" % ch)
    s = "".join(out)
    return s[:-3] if s.endswith(" ⏎ ") else s


def with_view(tail):
    """The seven view lines, then `tail` from line 8."""
    return VIEW7 + tail, "(view) ⏎ " + show_lines(tail)


def view_with(line, replacement, tail=b"s 0 0 0 1\n"):
    """The view with its line `line` (1-based) replaced, then `tail`."""
    lines = VIEW7.decode().split("\n")[:-1]
    lines[line - 1] = replacement
    return ("\n".join(lines) + "\n").encode() + tail, "view line %d: %s" % (line, replacement)


def whole(text):
    return text, show_lines(text) if text else "(empty file)"


SCENE_ARGS = ["render", "bad.nff", "--mode", "base", "--size", "8x6", "--threads", "1", "--png", "out.png",
              "--pfm", "out.pfm", "--stats", "out.json"]


def scene(category, name, text_shown, line, phrase):
    text, shown = text_shown
    add(category, name + " (BadScene)", {"bad.nff": text}, SCENE_ARGS, shown, line, phrase)


# wrong counts of numbers
scene("scene syntax", "sphere_3_numbers", with_view(b"s 0 0 0\n"), 8, "sphere needs 4 numbers, got 3")
scene("scene syntax", "sphere_5_numbers", with_view(b"s 0 0 0 1 2\n"), 8, "sphere needs 4 numbers, got 5")
scene("scene syntax", "cone_7_numbers", with_view(b"c 0 0 0 1 0 0 1\n"), 8, "needs 8 numbers, got 7")
scene("scene syntax", "material_7_numbers", with_view(b"f 1 1 1 1 0 0 0\ns 0 0 0 1\n"), 9,
      "material (f) needs 8 numbers, got 7 (the entity begins at line 8)")
scene("scene syntax", "light_4_numbers", with_view(b"l 1 2 3 4\ns 0 0 0 1\n"), 9,
      "light (l) needs 3 or 6 numbers, got 4")
scene("scene syntax", "background_2_numbers", with_view(b"b 1 1\ns 0 0 0 1\n"), 9, "needs 3 numbers, got 2")
scene("scene syntax", "from_2_numbers", view_with(2, "from 0 0"), 3,
      "from needs 3 numbers, got 2 (the entity begins at line 2)")
scene("scene syntax", "polygon_vertex_2_numbers", with_view(b"p 3\n0 0 0\n1 0\n0 1 0\n"), 8,
      "polygon (p) ends early: expected 3 vertices (9 numbers), got 8 numbers")
scene("scene syntax", "patch_vertex_3_numbers", with_view(b"pp 3\n0 0 0 0 0 1\n1 0 0\n0 1 0 0 0 1\n"), 8,
      "patch (pp) ends early: expected 3 vertices (18 numbers), got 15 numbers")
scene("scene syntax", "polygon_too_many_numbers", with_view(b"p 3\n0 0 0\n1 0 0\n0 1 0 7\n"), 11,
      "needs 9 numbers after its count, got more")
scene("scene syntax", "sphere_numbers_on_next_line", with_view(b"s 0 0 0 1\n2 3\n"), 9, "sphere needs 4 numbers, got 6")
scene("scene syntax", "number_where_entity_expected", whole(b"7\n" + VIEW7 + b"s 0 0 0 1\n"), 1,
      "number '7' where an entity was expected")
scene("scene syntax", "v_with_a_number", view_with(1, "v 3"), 1, "v takes no numbers, got 1")
# non-numbers, nan, inf, out of float range
scene("numbers", "non_number", with_view(b"s 0 0 abc 1\n"), 8, "'abc' is not a number")
scene("numbers", "nan", with_view(b"s 0 nan 0 1\n"), 8, "'nan' is not a finite number")
scene("numbers", "inf", with_view(b"s 0 0 0 inf\n"), 8, "'inf' is not a finite number")
scene("numbers", "minus_inf", with_view(b"f 1 1 1 -inf 0 0 0 1\ns 0 0 0 1\n"), 8, "is not a finite number")
scene("numbers", "1e999", with_view(b"s 1e999 0 0 1\n"), 8, "'1e999' is not a finite number")
scene("numbers", "beyond_float", with_view(b"s 0 0 0 1e39\n"), 8, "'1e39' is not a finite number")
scene("numbers", "hex_float", with_view(b"s 0x1p3 0 0 1\n"), 8, "is not a number")
scene("numbers", "two_dots", with_view(b"s 1.2.3 0 0 1\n"), 8, "'1.2.3' is not a number")
scene("numbers", "shine_nan", with_view(b"f 1 1 1 1 0 NaN 0 1\ns 0 0 0 1\n"), 8, "is not a finite number")
scene("numbers", "polygon_count_not_integer", with_view(b"p 3.5\n0 0 0\n1 0 0\n0 1 0\n"), 8, "is not an integer")
# resolution, angle
scene("numbers", "resolution_zero", view_with(7, "resolution 0 0"), 7, "resolution width: 0 is out of range")
scene("numbers", "resolution_negative_width", view_with(7, "resolution -16 12"), 7,
      "resolution width: -16 is out of range")
scene("numbers", "resolution_negative_height", view_with(7, "resolution 16 -12"), 7,
      "resolution height: -12 is out of range")
scene("numbers", "resolution_height_1", view_with(7, "resolution 16 1"), 7, "resolution height: 1 is out of range")
scene("numbers", "resolution_fraction", view_with(7, "resolution 16.5 12"), 7, "is not an integer")
scene("numbers", "angle_0", view_with(5, "angle 0"), 5, "angle must be between 0 and 180")
scene("numbers", "angle_180", view_with(5, "angle 180"), 5, "angle must be between 0 and 180")
scene("numbers", "angle_negative", view_with(5, "angle -30"), 5, "angle must be between 0 and 180")
# degenerate polygons
scene("geometry", "polygon_collinear_first_edges", with_view(b"p 4\n0 0 0\n1 0 0\n2 0 0\n0 1 0\n"), 8,
      "first two edges are zero or collinear")
scene("geometry", "polygon_zero_length_edge", with_view(b"p 3\n0 0 0\n0 0 0\n1 1 0\n"), 8,
      "first two edges are zero or collinear")
scene("geometry", "polygon_all_points_equal", with_view(b"p 3\n1 1 1\n1 1 1\n1 1 1\n"), 8, "degenerate polygon")
scene("geometry", "polygon_non_planar", with_view(b"p 4\n0 0 0\n1 0 0\n1 1 0\n0 1 0.5\n"), 8, "not planar: vertex 3")
scene("geometry", "polygon_2_vertices", with_view(b"p 2\n0 0 0\n1 0 0\n"), 8, "polygon vertex count: 2 is out of range")
scene("geometry", "polygon_0_vertices", with_view(b"s 0 0 0 1\np 0\n"), 9, "polygon vertex count: 0 is out of range")
scene("scene syntax", "polygon_ends_at_eof", with_view(b"s 0 0 0 1\np 4\n0 0 0\n1 0 0\n\n# end\n"), 9,
      "ends early: expected 4 vertices (12 numbers), got 6 numbers")
scene("scene syntax", "polygon_cut_by_next_entity", with_view(b"p 4\n0 0 0\n1 0 0\n1 1 0\ns 0 0 0 1\n"), 12,
      "polygon (p) ends early: expected 4 vertices (12 numbers), got 9 numbers (the entity begins at line 8)")
scene("geometry", "patch_collinear", with_view(b"pp 3\n0 0 0 0 0 1\n1 0 0 0 0 1\n2 0 0 0 0 1\n"), 8,
      "degenerate polygon")
scene("geometry", "patch_zero_normal", with_view(b"pp 3\n0 0 0 0 0 1\n1 0 0 0 0 0\n0 1 0 0 0 1\n"), 10,
      "patch vertex normal is zero")
scene("geometry", "patch_2_vertices", with_view(b"pp 2\n0 0 0 0 0 1\n1 0 0 0 0 1\n"), 8,
      "patch vertex count: 2 is out of range")
# cones, spheres
scene("geometry", "cone_coincident_ends", with_view(b"c 1 2 3 1  1 2 3 0.5\n"), 8, "cone ends coincide")
scene("geometry", "cone_opposite_radii", with_view(b"c 0 0 0 1  0 0 1 -0.5\n"), 8, "cone radii have opposite signs")
scene("geometry", "cone_opposite_radii_2", with_view(b"c 0 0 0 -1  0 0 1 0.5\n"), 8, "cone radii have opposite signs")
scene("geometry", "cone_both_radii_zero", with_view(b"c 0 0 0 0  0 0 1 0\n"), 8, "both cone radii are zero")
scene("geometry", "sphere_radius_zero", with_view(b"s 0 0 0 0\n"), 8, "sphere radius is zero")
scene("geometry", "sphere_radius_minus_zero", with_view(b"s 0 0 0 -0.0\n"), 8, "sphere radius is zero")
# entities, files
scene("scene syntax", "unknown_entity", with_view(b"s 0 0 0 1\nsphere 0 0 0 1\n"), 9, "unknown entity 'sphere'")
scene("textures", "missing_texture_file", with_view(b"texture image no-such-file.png 1 1\ns 0 0 0 1\n"), 8,
      "texture file 'no-such-file.png' cannot be read")
scene("scene syntax", "empty_file", whole(b""), 1, "empty scene file")
scene("scene syntax", "only_comments", whole(b"# one\n\n   # two\n\t\n"), 1, "empty scene file")
scene("scene syntax", "no_primitives", with_view(b"l 1 1 1\n\n# nothing else\n"), 8, "scene has no primitives")
# the viewpoint
scene("scene syntax", "missing_up", whole(b"v\nfrom 0 0 5\nat 0 0 0\nangle 45\nresolution 8 8\ns 0 0 0 1\n"), 1,
      "viewpoint is missing: up")
scene("scene syntax", "missing_resolution_and_angle", whole(b"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\ns 0 0 0 1\n"), 1,
      "viewpoint is missing: angle resolution")
scene("scene syntax", "missing_viewpoint", whole(b"l 1 1 1\ns 0 0 0 1\n"), 2,
      "viewpoint is missing: from at up angle resolution")
scene("geometry", "up_parallel_to_view", view_with(4, "up 0 0 -3"), 1, "up is zero or parallel to the view direction")
scene("geometry", "up_zero", view_with(4, "up 0 0 0"), 1, "up is zero or parallel to the view direction")
scene("geometry", "from_equals_at", view_with(3, "at 0 0 5"), 1, "from and at coincide")
scene("geometry", "from_and_at_too_far_apart", view_with(3, "at 0 0 -3e38"), 1, "from and at are too far apart")
# colours and materials
scene("numbers", "negative_material_colour", with_view(b"f 1 -0.5 1 1 0 0 0 1\ns 0 0 0 1\n"), 8,
      "material colour must be non-negative")
scene("numbers", "negative_light_colour", with_view(b"l 1 1 1 1 1 -1\ns 0 0 0 1\n"), 8,
      "light colour must be non-negative")
scene("numbers", "negative_background", with_view(b"b 0 0 -0.1\ns 0 0 0 1\n"), 8,
      "background colour must be non-negative")
scene("numbers", "negative_ambient", with_view(b"ambient -1 0 0\ns 0 0 0 1\n"), 8, "ambient colour must be non-negative")
scene("numbers", "negative_kd", with_view(b"f 1 1 1 -1 0 0 0 1\ns 0 0 0 1\n"), 8, "Kd must be non-negative")
scene("numbers", "negative_ks", with_view(b"f 1 1 1 1 -0.1 0 0 1\ns 0 0 0 1\n"), 8, "Ks must be non-negative")
scene("numbers", "negative_t", with_view(b"f 1 1 1 1 0 0 -0.5 1\ns 0 0 0 1\n"), 8, "T must be non-negative")
scene("numbers", "kd_over_1000", with_view(b"f 1 1 1 1001 0 0 0 1\ns 0 0 0 1\n"), 8, "Kd must be at most 1000")
scene("numbers", "light_over_1e6", with_view(b"l 1 1 1 2e6 1 1\ns 0 0 0 1\n"), 8,
      "light colour must be at most 1000000")
scene("numbers", "transparent_ior_zero", with_view(b"f 1 1 1 1 0 0 0.5 0\ns 0 0 0 1\n"), 8,
      "ior must be positive when T > 0")
scene("numbers", "transparent_ior_negative", with_view(b"f 1 1 1 1 0 0 0.5 -1.5\ns 0 0 0 1\n"), 8,
      "ior must be positive when T > 0")
# bytes
scene("scene syntax", "non_ascii_byte", with_view(b"s 0 0 0 1 \xc3\xa9\n"), 8, "byte 0xc3 is not printable ASCII")
scene("scene syntax", "control_byte", with_view(b"s 0 0 0 1\n\x01\n"), 9, "byte 0x01 is not printable ASCII")
scene("scene syntax", "non_ascii_before_comment", with_view(b"s 0 0 0 1 \xff # fine here \xff\n"), 8, "byte 0xff")
scene("scene syntax", "nul_byte", with_view(b"s 0 0 0 1\ns 0 0\x00 0 1\n"), 9, "byte 0x00")
# the superset
scene("scene syntax", "pop_without_push", with_view(b"s 0 0 0 1\npop\n"), 9, "pop without a matching push")
scene("scene syntax", "pop_twice", with_view(b"push\npop\npop\ns 0 0 0 1\n"), 10, "pop without a matching push")
scene("numbers", "scale_zero", with_view(b"scale 0\ns 0 0 0 1\n"), 8, "scale must be positive")
scene("numbers", "scale_negative", with_view(b"scale -2\ns 0 0 0 1\n"), 8, "scale must be positive")
scene("geometry", "rotate_zero_axis", with_view(b"rotate 0 0 0 45\ns 0 0 0 1\n"), 8, "rotation axis is zero")
scene("textures", "unknown_texture_kind", with_view(b"texture marble 1 1\ns 0 0 0 1\n"), 8,
      "unknown texture kind 'marble'")
scene("textures", "texture_scale_zero", with_view(b"texture checker 1 1 1 0 0 0 0 1\ns 0 0 0 1\n"), 8,
      "texture scales must be positive")
scene("geometry", "box_zero_size", with_view(b"box 0 0 0 1 0 1\n"), 8, "box has zero size along an axis")
scene("geometry", "disk_zero_normal", with_view(b"disk 0 0 0 0 0 0 1\n"), 8, "disk normal is zero")
scene("geometry", "disk_zero_radius", with_view(b"disk 0 0 0 0 0 1 0\n"), 8, "disk radius must be positive")
scene("geometry", "capped_cone_negative_radius", with_view(b"cc 0 0 0 -1 0 0 1 -1\n"), 8,
      "capped cone radii must be non-negative")
# line numbers past comments, blank lines and multi-line polygons
scene("scene syntax", "line_after_polygon_and_comments",
      with_view(b"# c\n\np 3\n0 0 0\n1 0 0\n\n0 1 0\n  # indented comment\ns 1 2 3\n"), 16,
      "sphere needs 4 numbers, got 3")
scene("scene syntax", "crlf_line", with_view(b"s 0 0 0 1\r\ns 0 0 0\r\n"), 9, "sphere needs 4 numbers, got 3")

# --- tests/test_cli.cpp: CliBadScene and the single bad-scene tests -------------------------

CLI_VIEW7 = b"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 6\n"


def cli_scene(category, name, tail, line, phrase, with_view7=True):
    text = (CLI_VIEW7 if with_view7 else b"") + tail
    shown = ("(view) ⏎ " if with_view7 else "") + (show_lines(tail) if tail else "(empty file)")
    add(category, name + " (CliBadScene)", {"bad.nff": text}, SCENE_ARGS, shown, line, phrase)


cli_scene("scene syntax", "sphere_3_numbers", b"s 0 0 0\n", 8, "sphere needs 4 numbers, got 3")
cli_scene("numbers", "not_a_number", b"s 0 0 x 1\n", 8, "'x' is not a number")
cli_scene("numbers", "nan", b"f 1 1 1 nan 0 0 0 1\ns 0 0 0 1\n", 8, "not a finite number")
cli_scene("geometry", "degenerate_polygon", b"p 3\n0 0 0\n1 1 1\n2 2 2\n", 8, "degenerate polygon")
cli_scene("scene syntax", "unknown_entity", b"# c\nq 1 2\n", 9, "unknown entity 'q'")
cli_scene("scene syntax", "empty", b"", 1, "empty scene file", with_view7=False)
cli_scene("scene syntax", "no_view", b"s 0 0 0 1\n", 1, "viewpoint is missing", with_view7=False)
cli_scene("scene syntax", "non_ascii", b"s 0 0 0 1\xe9\n", 8, "not printable ASCII")
cli_scene("scene syntax", "polygon_ends_early", b"p 4\n0 0 0\n1 0 0\n", 8, "ends early")
cli_scene("textures", "missing_texture", b"texture image nope.png 1 1\ns 0 0 0 1\n", 8, "cannot be read")

add("scene syntax", "BadSceneWithDefaultModeIsStillBadInput", {"bad.nff": CLI_VIEW7 + b"s 0 0 0\n"},
    ["render", "bad.nff", "--png", "out.png"], "(view) ⏎ s 0 0 0  (default mode)", 8,
    "sphere needs 4 numbers, got 3")
add("geometry", "AbsoluteScenePathIsNamedAsGiven", {"bad.nff": CLI_VIEW7 + b"s 0 0 0 0\n"},
    ["render", "{tmp}/bad.nff", "--mode", "base"], "(view) ⏎ s 0 0 0 0  (absolute path)", 8,
    "sphere radius is zero")
add("scene syntax", "MissingFileIsInputError (Scene)", {}, ["render", "/nonexistent/epsray/none.nff", "--mode", "base"],
    "/nonexistent/epsray/none.nff", None, "none.nff")

# Only regular files are read (InputFiles in tests/test_scene.cpp).
add("scene syntax", "DevicesAndFifosAreRefusedAtOnce (device)", {}, ["render", "/dev/zero", "--mode", "base"],
    "/dev/zero", 0, "not a regular file")
add("scene syntax", "DevicesAndFifosAreRefusedAtOnce (folder)", {}, ["render", "{tmp}", "--mode", "base"],
    "a folder as the scene", 0, "is a folder")
# Transforms checked like the primitives they make (Transforms in tests/test_scene.cpp).
scene("geometry", "scale_overflow", with_view(b"scale 1e30\nscale 1e30\ns 0 0 0 1\n"), 9, "scale is beyond float range")
scene("geometry", "scale_underflow", with_view(b"scale 1e-30\nscale 1e-30\nbox 0 0 0 1 1 1\n"), 9,
      "scale underflows to zero")
scene("geometry", "box_underflow", with_view(b"scale 1e-19\nbox 0 0 0 1e-20 1 1\n"), 9,
      "box size underflows to zero once scaled")
scene("geometry", "translate_overflow", with_view(b"translate 3e38 0 0\ntranslate 3e38 0 0\ns 0 0 0 1\n"), 9,
      "translation is beyond float range")
scene("geometry", "sphere_centre_overflow", with_view(b"scale 1e20\ns 1e19 0 0 1\n"), 9,
      "sphere centre is beyond float range")

# --- camera path files: BadPath in tests/test_scene.cpp ------------------------------------

GOOD_SCENE = (b"b 0.1 0.2 0.3\n"
              b"v\nfrom 0 -5 2\nat 0 0 0.5\nup 0 0 1\nangle 45\nhither 0.1\nresolution 10 8\n"
              b"l 3 -3 5\n"
              b"l -2 -4 3 0.4 0.3 0.2\n"
              b"f 0.9 0.9 0.9 0.7 0.3 20 0 1\n"
              b"p 4\n-4 -4 0\n4 -4 0\n4 4 0\n-4 4 0\n"
              b"f 1 0.3 0.3 0.6 0.2 10 0.4 1.4\n"
              b"s 0 0 1 0.8\n")
TWO_FRAMES = b"# two cameras\n0 -5 2  0 0 0.5  0 0 1  45\n\n3 -4 3  0 0 0.5  0 0 1  30\n"
OK = b"0 0 5 0 0 0 0 1 0 45\n"
PATH_ARGS = ["render", "good.nff", "--path", "bad.path", "--frame", "0", "--mode", "base", "--size", "8x6",
             "--png", "out.png"]


def path(name, text, line, phrase, shown=None):
    add("camera paths", name + " (BadPath)", {"good.nff": GOOD_SCENE, "bad.path": text}, PATH_ARGS,
        shown or (show_lines(text) if text else "(empty file)"), line, phrase)


path("nine_numbers", OK + b"0 0 5 0 0 0 0 1 0\n", 2, "camera needs 10 numbers (from, at, up, angle), got 9",
     "(ok) ⏎ 0 0 5 0 0 0 0 1 0")
path("eleven_numbers", b"# c\n" + OK + OK + b"0 0 5 0 0 0 0 1 0 45 1\n", 4, "camera needs 10 numbers",
     "# c ⏎ (ok) ⏎ (ok) ⏎ 0 0 5 0 0 0 0 1 0 45 1")
path("non_number", OK + b"0 0 5 0 x 0 0 1 0 45\n", 2, "'x' is not a number", "(ok) ⏎ 0 0 5 0 x 0 0 1 0 45")
path("nan", OK + b"0 0 5 0 0 0 0 1 0 nan\n", 2, "'nan' is not a finite number", "(ok) ⏎ 0 0 5 0 0 0 0 1 0 nan")
path("angle_zero", OK + OK + b"0 0 5 0 0 0 0 1 0 0\n", 3, "angle must be between 0 and 180",
     "(ok) ⏎ (ok) ⏎ 0 0 5 0 0 0 0 1 0 0")
path("angle_180", b"0 0 5 0 0 0 0 1 0 180\n", 1, "angle must be between 0 and 180")
path("angle_negative", b"\n\n0 0 5 0 0 0 0 1 0 -45\n", 3, "angle must be between 0 and 180")
path("angle_too_big", OK + b"0 0 5 0 0 0 0 1 0 270\n", 2, "angle must be between 0 and 180",
     "(ok) ⏎ 0 0 5 0 0 0 0 1 0 270")
path("from_equals_at", OK + b"1 1 1 1 1 1 0 1 0 45\n", 2, "from and at coincide", "(ok) ⏎ 1 1 1 1 1 1 0 1 0 45")
path("up_too_large", OK + b"0 0 0  1 1 0  3e38 -3e38 0  45\n", 2, "up is too large",
     "(ok) ⏎ 0 0 0  1 1 0  3e38 -3e38 0  45")
path("up_parallel", OK + b"0 0 5 0 0 0 0 0 1 45\n", 2, "up is zero or parallel", "(ok) ⏎ 0 0 5 0 0 0 0 0 1 45")
path("non_ascii", OK + b"0 0 5 0 0 0 0 1 0 45 \xe2\x80\x94\n", 2, "is not printable ASCII",
     "(ok) ⏎ 0 0 5 0 0 0 0 1 0 45 \\xe2\\x80\\x94")
path("empty", b"", 1, "camera path has no frames")
path("only_comments", b"# nothing\n\n# here\n", 1, "camera path has no frames")

# --- tests/test_cli.cpp: CliBadFlags -------------------------------------------------------

FLAG_FILES = {"good.nff": GOOD_SCENE, "two.path": TWO_FRAMES, "bad.path": TWO_FRAMES + b"0 0 5 0 0 0 0 1 0\n",
              "adir/": None}


def render_args(extra):
    return ["render", "good.nff", "--mode", "base", "--png", "out.png", "--pfm", "out.pfm", "--stats",
            "out.json"] + extra


def flag(category, name, args, phrase, shown=None, file_input=False, line=None):
    add(category, name + " (CliBadFlags)", FLAG_FILES, args, shown or " ".join(args), line, phrase,
        file_input=file_input)


def rflag(name, extra, phrase, **k):
    flag("flags and outputs", name, render_args(extra), phrase, shown="render ... " + " ".join(extra), **k)


rflag("size_0x0", ["--size", "0x0"], "--size")
rflag("size_abc", ["--size", "abc"], "--size")
rflag("size_height_1", ["--size", "16x1"], "--size")
rflag("size_no_height", ["--size", "16x"], "--size")
rflag("size_negative", ["--size", "-4x8"], "--size")
rflag("threads_0", ["--threads", "0"], "--threads")
rflag("threads_negative", ["--threads", "-2"], "--threads")
rflag("threads_word", ["--threads", "many"], "--threads")
rflag("eps_negative", ["--eps", "-1"], "--eps")
rflag("eps_nan", ["--eps", "nan"], "--eps")
rflag("eps_inf", ["--eps", "inf"], "--eps")
rflag("eps_trailing_junk", ["--eps", "0.1x"], "--eps")
rflag("mode_foo", ["--mode", "foo"], "--mode")
rflag("upsample_0", ["--upsample", "0"], "--upsample")
rflag("reuse_age_negative", ["--reuse-age", "-1"], "--reuse-age")
rflag("lf_depth_17", ["--lf-depth", "17"], "--lf-depth")
rflag("defer_pixels_negative", ["--defer-pixels", "-1"], "--defer-pixels")
rflag("failed_split_pixels_nan", ["--failed-split-pixels", "nan"], "--failed-split-pixels")
rflag("min_prim_pixels_negative", ["--min-prim-pixels", "-5"], "--min-prim-pixels")
rflag("reproject_unknown", ["--reproject", "raster"], "--reproject")
rflag("span_negative", ["--span", "-1"], "--span")
rflag("tile_order_unknown", ["--tile-order", "random"], "--tile-order")
rflag("object_gate_maybe", ["--object-gate", "maybe"], "--object-gate")
rflag("plain_frames_yes", ["--plain-frames", "yes"], "--plain-frames")
rflag("light_cache_maybe", ["--light-cache", "maybe"], "--light-cache")
rflag("mirror_yes", ["--mirror", "yes"], "--mirror")
rflag("unknown_option", ["--bogus"], "--bogus")
rflag("frame_without_path", ["--frame", "0"], "--frame")
rflag("frame_out_of_range", ["--path", "two.path", "--frame", "2"], "--frame")
rflag("frame_negative", ["--path", "two.path", "--frame", "-1"], "--frame")
rflag("png_folder_missing", ["--png", "no-such-dir/a.png"], "no-such-dir")
rflag("pfm_folder_missing", ["--pfm", "no-such-dir/a.pfm"], "no-such-dir")
rflag("stats_folder_missing", ["--stats", "no-such-dir/a.json"], "no-such-dir")
rflag("png_is_a_folder", ["--png", "adir"], "adir")
flag("flags and outputs", "scene_is_a_folder", ["render", "adir", "--mode", "base", "--png", "out.png"], "adir",
     file_input=True)
flag("flags and outputs", "flag_without_value",
     ["render", "good.nff", "--mode", "base", "--stats", "out.json", "--png"], "--png")
flag("flags and outputs", "no_command", [], "command", shown="(no arguments)")
flag("flags and outputs", "unknown_command", ["paint", "good.nff"], "paint")
flag("flags and outputs", "no_scene", ["render", "--mode", "base"], "SCENE")
flag("flags and outputs", "two_scenes", ["render", "good.nff", "good.nff"], "unexpected argument")
flag("flags and outputs", "missing_scene_file", ["render", "none.nff", "--mode", "base", "--png", "out.png"],
     "none.nff", file_input=True)
flag("camera paths", "missing_path_file", render_args(["--path", "none.path"]), "none.path",
     shown="render ... --path none.path", file_input=True)
flag("camera paths", "bad_path_file_other_frame", render_args(["--path", "bad.path", "--frame", "0"]), "bad.path:5: ",
     shown="render ... --path bad.path --frame 0 (line 5: 0 0 5 0 0 0 0 1 0)", file_input=True, line=5)
flag("camera paths", "walk_without_path", ["walk", "good.nff", "--mode", "base"], "--path")
flag("camera paths", "walk_bad_path_file", ["walk", "good.nff", "--path", "bad.path", "--out-dir", "f", "--png"],
     "bad.path:5: ", shown="walk ... --path bad.path (line 5: 0 0 5 0 0 0 0 1 0)", file_input=True, line=5)
flag("flags and outputs", "walk_out_dir_is_a_file",
     ["walk", "good.nff", "--path", "two.path", "--out-dir", "good.nff", "--png"], "--out-dir")
flag("flags and outputs", "walk_out_dir_parent_missing",
     ["walk", "good.nff", "--path", "two.path", "--out-dir", "no-such-dir/f", "--png"], "no-such-dir")
flag("flags and outputs", "walk_png_without_out_dir", ["walk", "good.nff", "--path", "two.path", "--png"], "--out-dir")
flag("flags and outputs", "walk_bad_scene_file",
     ["walk", "none.nff", "--path", "two.path", "--out-dir", "f", "--png"], "none.nff", file_input=True)

# Empty names, a walk's --frame, switches given values, names with control characters.
rflag("png_empty", ["--png", ""], "--png ''")
rflag("pfm_empty_joined", ["--pfm="], "--pfm ''")
rflag("stats_empty", ["--stats", ""], "--stats ''")
rflag("path_empty", ["--path", ""], "--path ''")
flag("flags and outputs", "scene_empty", ["render", "", "--png", "out.png"], "SCENE ''")
flag("flags and outputs", "walk_frame", ["walk", "good.nff", "--path", "two.path", "--frame", "1"],
     "--frame is for render only")
rflag("switch_with_value", ["--quiet=yes"], "--quiet takes no value")
rflag("joined_value_checked", ["--eps=-1"], "bad --eps '-1'")
rflag("unknown_option_joined", ["--bogus=1"], "unknown option '--bogus'")
flag("flags and outputs", "newline_in_scene_name", ["render", "no\nsuch.nff", "--png", "out.png"],
     '"no\\nsuch.nff":', shown="render 'no⏎such.nff'", file_input=True)

# --- tests/test_viewer.cpp: bad viewer scripts, checked before any window opens -----------

VIEW_ARGS = ["view", str(VIEW_SCENE), "--script", "bad.script"]


def script(name, text, phrase, line=2, prefix=b"refine\n", test="BadLinesNameTheLine", display=None):
    add("viewer scripts", name + " (" + test + ")", {"bad.script": prefix + text}, VIEW_ARGS,
        show_lines(prefix + text), line, phrase, display=display)


script("frames_no_count", b"frames\n", "expected 'frames N'")
script("frames_0", b"frames 0\n", "frames")
script("key_P", b"key P 3\n", "not one of W A S D Q E")
script("press_W", b"press W\n", "cannot press 'W'")
script("mode_fancy", b"mode fancy\n", "not image, reasons, paths or cells")
script("pick_one_number", b"pick 0.5\n", "expected 'pick FX FY'")
script("pick_outside", b"pick 1.5 0.5\n", "fractions of the image")
script("eps_negative", b"eps -1\n", "eps must be")
script("hud_maybe", b"hud maybe\n", "hud on")
script("screenshot_folder_missing", b"screenshot /no/such/folder/x.png\n", "does not exist")
script("unknown_command", b"jump\n", "unknown command 'jump'")
# ViewerCli.BadScriptIsBadInputBeforeAnyWindow runs with DISPLAY=:0; here DISPLAY is unset, and
# once more set to :0 as in the test (no X server needs to be there: the script fails first).
script("fly", b"fly 3\n", "bad.script:2: unknown command 'fly' (frames, refine, key, drag, press, mode, pick, eps, "
       "hud, screenshot, quit)", prefix=b"frames 1\n", test="BadScriptIsBadInputBeforeAnyWindow")
script("fly, DISPLAY=:0", b"fly 3\n", "bad.script:2: unknown command 'fly'", prefix=b"frames 1\n",
       test="BadScriptIsBadInputBeforeAnyWindow", display=":0")
add("viewer scripts", "no_display (NoDisplayIsOneLineAndExitTwo)", {},
    ["view", str(VIEW_SCENE), "--size", "160x120"], "view sphere.nff, DISPLAY unset", None,
    "epsray: view needs a display", file_input=False)


# --- running ------------------------------------------------------------------------------------

class Result:
    def __init__(self, case, code, err, out, written, tmp):
        self.case = case
        self.code = code
        self.message = err.rstrip("\n").replace(tmp, "<tmp>")
        self.lines = err.count("\n")
        self.out = out
        self.written = written
        self.problems = []
        c = case
        if code != 2:
            self.problems.append("exit %s, not 2" % code)
        if self.lines != 1 or not err.endswith("\n"):
            self.problems.append("stderr has %d lines, not one" % self.lines)
        m = re.match(r"^(.+?):(\d+): ", self.message)
        if c.file_input:
            if not m:
                self.problems.append("no file:line: in the message")
            elif int(m.group(2)) == 0:
                self.problems.append("`file:0:`, line 0: the file could not be opened, so no line is named")
            elif c.line is not None and int(m.group(2)) != c.line:
                self.problems.append("line %s, the test expects %d" % (m.group(2), c.line))
        if c.phrase and c.phrase not in err:
            self.problems.append("lacks the test's phrase '%s'" % c.phrase)
        if written:
            self.problems.append("wrote " + ", ".join(written))


def listing(folder):
    return sorted(str(p.relative_to(folder)) + ("/" if p.is_dir() else "") for p in Path(folder).rglob("*"))


def run_case(case):
    with tempfile.TemporaryDirectory(prefix="epsray-bad-input-") as tmp:
        for name, data in case.files.items():
            if name.endswith("/"):
                os.makedirs(os.path.join(tmp, name), exist_ok=True)
            else:
                with open(os.path.join(tmp, name), "wb") as f:
                    f.write(data)
        before = listing(tmp)
        env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
        if case.display is not None:
            env["DISPLAY"] = case.display
        args = [a.replace("{tmp}", tmp) for a in case.args]
        try:
            p = subprocess.run([str(BINARY)] + args, cwd=tmp, env=env, capture_output=True, timeout=60)
            code, err, out = p.returncode, p.stderr.decode("utf-8", "replace"), p.stdout.decode("utf-8", "replace")
        except subprocess.TimeoutExpired:
            code, err, out = "timeout", "", ""
        written = [n for n in listing(tmp) if n not in before]
        return Result(case, code, err, out, written, tmp)


def cell(text, code=True):
    text = text.replace("|", "\\|")
    if not code:
        return text
    ticks = "``" if "`" in text else "`"
    pad = " " if "`" in text else ""
    return ticks + pad + text + pad + ticks


def markdown(results):
    by_cat = {c: [r for r in results if r.case.category == c] for c in CATEGORIES}
    out = ["# Bad input: every malformed-input case the tests check", ""]
    out.append(
        "Bad input (a scene, a camera path, a viewer script, a flag) makes `build/epsray` print one line, "
        "`file:line: what is wrong` (flags, which are not in a file, start with `epsray:`), and exit with "
        "status 2, writing nothing (README, *Using it*). This page lists every such case the test suite "
        "checks: the bad scenes of `tests/test_scene.cpp` (`BadScene`, `BadPath`) and `tests/test_cli.cpp` "
        "(`CliBadScene`, `CliBadFlags` and the single tests), and the bad viewer scripts of "
        "`tests/test_viewer.cpp` (`ViewerScript.BadLinesNameTheLine`, `ViewerCli`). The case column gives "
        "the test's own name for the case and, in brackets, the test. The table is not written by hand: "
        "`tools/bad-input-table.py` holds the case texts, copied from the tests, writes each case's files into "
        "a fresh temporary folder, runs the built binary there (`render` for scenes and path files with "
        "`--png`, `--pfm` and `--stats` outputs, `view SCENE --script bad.script` with `DISPLAY` unset for "
        "scripts, which are checked before any window opens) and records its exit code and its stderr. In "
        "the input column `(view)` stands for the seven viewpoint lines the tests put first (so the first "
        "line after them is line 8), `(ok)` for a good path line, `⏎` for a line break; `<tmp>` in a "
        "message is the temporary folder. To remake it after a build: `python3 tools/bad-input-table.py` "
        "(`--check` runs the cases and writes nothing).")
    out.append("")
    counts = ", ".join("%s %d" % (c, len(by_cat[c])) for c in CATEGORIES)
    out.append("%d cases: %s." % (len(results), counts))
    out.append("")
    for c in CATEGORIES:
        out.append("## " + c[0].upper() + c[1:])
        out.append("")
        out.append("| category | case | input | exit code | message |")
        out.append("|---|---|---|---|---|")
        for r in by_cat[c]:
            out.append("| %s | %s | %s | %s | %s |" % (c, cell(r.case.name, code=False), cell(r.case.shown),
                                                        r.code, cell(r.message)))
        out.append("")
    odd = [r for r in results if r.problems]
    out.append("## Cases that differ from the rule")
    out.append("")
    if not odd:
        out.append("None: every case exits 2 with one line, file inputs name `file:line:` with a line of the "
                   "file, and nothing is written.")
    else:
        out.append("Every other case exits 2 with one line, names `file:line:` (file inputs) with the line "
                   "the test expects, and writes nothing. These do not quite:")
        out.append("")
        for r in odd:
            out.append("- %s (%s): %s." % (r.case.name, r.case.category, "; ".join(r.problems)))
    out.append("")
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="run the cases, write nothing")
    args = ap.parse_args()
    if not os.access(BINARY, os.X_OK):
        sys.exit("%s is not built (tools/run-main.sh or cmake builds it)" % BINARY)
    results = [run_case(c) for c in CASES]
    odd = [r for r in results if r.problems]
    for r in odd:
        print("%s / %s: %s" % (r.case.category, r.case.name, "; ".join(r.problems)))
    print("%d cases, %d differ from the rule" % (len(results), len(odd)))
    if args.check:
        return 1 if odd else 0
    DOC.write_text(markdown(results), encoding="utf-8")
    print("wrote", DOC.relative_to(ROOT))
    return 0


if __name__ == "__main__":
    sys.exit(main())
