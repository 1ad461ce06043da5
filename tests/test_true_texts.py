"""The texts a user reads say what runs: the example scene's solver.method comment and `gfmd run`'s progress
lines name the algorithms of the chain that `gfmd.chains` picks and that curve.csv records as having relaxed the
steps; the process's internals (FFT backends and plans, heap, BLAS threads) are printed with --verbose only."""

import re

import pandas as pd
import pytest

import gfmd_contact as gc
from gfmd.chains import labels
from gfmd.loading import chain, settings_of
from gfmd_contact.cli import build_parser, main
from gfmd_contact.core.model import build_model
from gfmd_contact.core.scene import example_scene_text, scene_to_toml

#: the law names of the example scene's comment → the scene keys that make that law (on the example scene)
LAWS = {"hard-wall": {"interface.law": "hard-wall"}, "cohesive": {"interface.law": "cohesive"},
        "cohesive with tangential_ratio > 0": {"interface.law": "cohesive", "interface.tangential_ratio": 0.5},
        "cohesive-wall": {"interface.law": "cohesive-wall"}}
#: words of the process's internals (`gfmd.loading.INTERNALS`)
INTERNAL_WORDS = ("heap", "BLAS", "FFTW", "wisdom", "GFMD_JIT", "backends")


def _method_comment():
    """The comment of the example scene's [solver] method key, its continuation lines joined."""
    lines = example_scene_text().splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("method = "))
    text = [lines[start].split("#", 1)[1]]
    for line in lines[start + 1:]:
        if not line.lstrip().startswith("#") or not line.startswith(" "):
            break
        text.append(line.split("#", 1)[1])
    return " ".join(t.strip() for t in text)


def _chain_labels(scene):
    return labels(chain(build_model(scene), settings_of(scene)), settings_of(scene))


def _user_law_scene(scene):
    from test_user_law import eq3

    law = eq3(scene.work_normal, scene.interface.length_normal, name="eq3")
    return gc.with_law(scene, law)


def test_example_scene_names_the_first_algorithm_of_each_laws_chain():
    """The comment says, law by law, which algorithm relaxes a step first under method = "fire"; each claim is
    the first label of the chain gfmd.chains picks for that law; "verlet" is Verlet for every step."""
    comment = _method_comment()
    claims = dict(re.findall(r"(hard-wall|cohesive with tangential_ratio > 0|cohesive-wall|cohesive|user): ([\w-]+)",
                             comment))
    assert set(claims) == set(LAWS) | {"user"}, comment
    example = gc.example_scene()
    assert example.solver.method == "fire" and '"fire" (default)' in comment
    for law, keys in LAWS.items():
        assert _chain_labels(gc.change(example, keys))[0] == claims[law], law
    assert _chain_labels(_user_law_scene(example))[0] == claims["user"]
    verlet = gc.change(example, {"solver.method": "verlet"})
    for keys in LAWS.values():
        assert set(_chain_labels(gc.change(verlet, keys))) == {"verlet"}
    assert '"verlet": the seed\'s damped Stormer-Verlet for every step, every law' in comment
    assert "fast default" not in comment


def _small(law="cohesive"):
    return gc.default_scene().replace(**{
        "surface.nodes": 256, "surface.length": 320e-9, "surface.realizations": 1,
        "surface.rolloff_wavelength": 160e-9, "surface.rollon_wavelength": 10e-9, "interface.length_normal": 2.5e-9,
        "interface.law": law, "loading.steps": 4, "loading.final_penetration": 4e-9,
        "loading.initial_separation": 20e-9, "output.workers": 1})


def _run(tmp_path, scene, *flags):
    scene_file = tmp_path / "s.toml"
    scene_file.write_text(scene_to_toml(scene))
    out = tmp_path / "out"
    assert main(["run", str(scene_file), "--out", str(out), "--no-plot", "--quiet", *flags]) == 0
    return out


def _described(text):
    """The algorithm labels of a chain in words: "ncg (then fire where it stalls)" → ["ncg", "fire"]."""
    first, _, rest = text.partition(" (then ")
    return [first] + (rest.split(" where it stalls")[0].split(" → ") if rest else [])


@pytest.mark.parametrize("law", ["cohesive", "hard-wall"])
def test_progress_lines_name_the_algorithms_that_relaxed_the_steps(tmp_path, capsys, law):
    """The scene line's "method GFMD ..." and the "algorithms:" line name the chain whose algorithms curve.csv's
    algorithm column records, first algorithm first; no line calls the chain an integrator."""
    out = _run(tmp_path, _small(law))
    err = capsys.readouterr().err
    scene_line = re.search(r"method GFMD (.+?), estimated peak memory", err).group(1)
    chain_line = re.search(r"  - algorithms: (.+?) \(gfmd\.chains", err).group(1)
    assert scene_line == chain_line
    named = _described(chain_line)
    ran = pd.read_csv(out / "curve.csv")["algorithm"].astype(str)
    assert {part for a in ran for part in a.split("→")} <= set(named), (named, set(ran))
    assert ran.str.split("→").str[0].eq(named[0]).all(), (named, list(ran))
    assert "integrator" not in err


@pytest.mark.parametrize("verbose", [False, True])
def test_internals_are_printed_with_verbose_only(tmp_path, capsys, verbose):
    """A small run's default stderr has none of the process's internals; --verbose prints them; meta.json keeps
    them either way."""
    out = _run(tmp_path, _small(), *(["--verbose"] if verbose else []))
    err = capsys.readouterr().err
    shown = [w for w in INTERNAL_WORDS if w in err]
    assert set(shown) >= {"heap", "BLAS", "backends"} if verbose else shown == [], shown
    meta = (out / "meta.json").read_text()
    assert all(w in meta for w in ("heap", "BLAS threads", "backends"))


def test_help_says_what_runs(capsys):
    """`gfmd --help` names profiles and 2+1-D surfaces, displacement and force control; --method fire is not
    called an integrator."""
    text = build_parser().format_help()
    assert "2+1-D surfaces" in text and "force control" in text
    run = build_parser()._subparsers._group_actions[0].choices["run"].format_help()
    assert "--verbose" in run and "integrator" not in run
