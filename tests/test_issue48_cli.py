"""Issue 48 on the command line: `fastbearing bearings`, the top-level description, --bearing NAME|FILE."""

import json

from conftest import cli_run

from fastbearing import cli
from fastbearing.report.catalogue import shipped_bearings, shipped_bearings_text


def test_bearings_lists_the_shipped_bearings(tmp_path):
    out = cli_run("bearings", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert out.stdout.rstrip("\n") == shipped_bearings_text(shipped_bearings())
    assert "6205" in out.stdout and "Where the numbers come from" in out.stdout
    js = cli_run("bearings", "--json", cwd=tmp_path)
    assert js.returncode == 0, js.stderr
    entries = json.loads(js.stdout)
    assert isinstance(entries, list) and [e["name"] for e in entries] == [e["name"] for e in shipped_bearings()]
    six = next(e for e in entries if e["name"] == "6205")
    assert (six["bore"], six["outer_diameter"], six["width"], six["C"], six["C0"]) == (25, 52, 15, 14800, 7800)
    assert six["units"]["C"] == "N" and six["units"]["bore"] == "mm"
    assert cli_run("bearings", "--nonsense").returncode == 2


def test_help_says_what_fastbearing_is_and_that_a_name_does():
    parser = cli.build_parser()
    text = parser.format_help()
    for words in ("deep-groove", "four-point", "tapered roller", "TDO", "ISO 281", "DMIG", "ROSS",
                  "Units: N, mm, rad", "bearings"):
        assert words in " ".join(text.split()), words
    sub = parser._subparsers._group_actions[0].choices
    for command in ("solve", "bearing"):
        help_text = " ".join(sub[command].format_help().split())
        assert "NAME|FILE.toml" in help_text and "fastbearing bearings lists them" in help_text, command
    loadzone = sub["plot"]._subparsers._group_actions[0].choices["loadzone"]
    assert "NAME|FILE.toml" in loadzone.format_help()
