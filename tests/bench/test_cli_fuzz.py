"""Fuzzing the command line: generated bad input to `run`, `robot`, `compare`, `demo`, `sweep`
(flags and TOML spec files) and `report`, each built from a valid base by breaking one thing.

Every input must be refused before anything runs: exit status 2, exactly one stderr line
`centrobench: error: ...` naming what is wrong, no traceback, and no file made or changed.
`main` runs in-process, in a fresh temporary working directory per example (the default
outputs, such as results/NAME, are relative), with every runner replaced by one that raises:
an input that is not bad after all fails the test instead of running.

2,000 examples in all (see EXAMPLES; about 20 s), derandomized: every run tests the same ones.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import re
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from bench.cli import main
from bench.limits import (
    CONTROL_PERIOD_S,
    FRICTION_MAX,
    MASS_RANGE_KG,
    MAX_EPISODE_SECONDS,
    MAX_EPISODES,
    MAX_HORIZON,
    MAX_PUSH_COUNT,
    MAX_PUSH_DV,
    MAX_PUSH_IMPULSE_NS,
    MAX_WORKERS,
    SCALE_RANGE,
    SEED_LIMIT,
)
from bench.push_protocol import PushProtocol
from bench.scenarios import WALK_STEPS
from tests.bench.test_cli import stub_runners

EXAMPLES = {"flags": 800, "structure": 150, "spec": 700, "toml": 200, "report": 150}
FUZZ = settings(
    deadline=None,
    derandomize=True,
    database=None,  # nothing written to .hypothesis/
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)

# ------------------------------------------------------------------ running one bad input


class Ran(Exception):
    """Raised by the stand-ins of everything that runs: bad input must not get that far."""


@pytest.fixture(scope="module", autouse=True)
def nothing_runs() -> Iterator[None]:
    with pytest.MonkeyPatch.context() as patch:
        stub_runners(patch, "a generated input got as far as running something", Ran)
        yield


def _tree(root: Path) -> dict[str, tuple[int, int]]:
    """Every file and folder under `root`: relative path -> (size, mtime in ns)."""
    result = {}
    for folder, names, files in os.walk(root):
        for name in names + files:
            path = Path(folder, name)
            info = path.lstat()
            result[str(path.relative_to(root))] = (info.st_size, info.st_mtime_ns)
    return result


def refused(argv: list[str], files: dict[str, bytes | None] | None = None) -> str:
    """Run `main(argv)` in a fresh temporary working directory holding `files` (name ->
    content, None for a folder); assert the one-line refusal and that nothing in that
    directory appeared or changed. Returns the message after "centrobench: error: "."""
    with tempfile.TemporaryDirectory(prefix="centrobench-fuzz-") as folder:
        root = Path(folder)
        for name, content in (files or {}).items():
            if content is None:
                (root / name).mkdir(parents=True)
            else:
                (root / name).parent.mkdir(parents=True, exist_ok=True)
                (root / name).write_bytes(content)
        before = _tree(root)
        out, err = io.StringIO(), io.StringIO()
        cwd = os.getcwd()
        os.chdir(root)
        try:
            with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
                status = main(argv)
        finally:
            os.chdir(cwd)
        after = _tree(root)
    text = err.getvalue()
    assert status == 2, (argv, status, text)
    assert "Traceback" not in text
    lines = text.splitlines()
    assert len(lines) == 1, (argv, text)
    assert lines[0].startswith("centrobench: error: "), lines
    assert after == before, (argv, set(after) ^ set(before))
    return lines[0].removeprefix("centrobench: error: ")


# --------------------------------------------------------------------- bad values as text

_TEXT = st.characters(exclude_categories=("Cs", "Cc"))
_JUNK = st.text(_TEXT, max_size=10)


def _parses(kind: type, text: str) -> bool:
    try:
        kind(text)
    except ValueError:
        return False
    return True


def _below(limit: float, strict: bool) -> st.SearchStrategy[float]:
    """Finite floats below `limit` (or equal to it when `strict`: the range excludes it);
    the filter drops -0.0 below a limit of 0.0, which is no smaller."""
    return st.floats(max_value=limit, allow_nan=False, allow_infinity=False).filter(
        lambda x: x < limit or (strict and x == limit)
    )


def _above(limit: float) -> st.SearchStrategy[float]:
    return st.floats(min_value=limit, allow_nan=False, allow_infinity=False).filter(
        lambda x: x > limit
    )


def bad_number(low: float, high: float, strict: bool = False) -> st.SearchStrategy[str]:
    """Text that is no finite number in [low, high] ((low, high] when `strict`)."""
    choices = [
        st.sampled_from(["nan", "inf", "-inf", "NaN", "Infinity", "1e400", "-1e999", ""]),
        _JUNK.filter(lambda text: not _parses(float, text)),
    ]
    if math.isfinite(low):
        choices.append(_below(low, strict).map(repr))
    if math.isfinite(high):
        choices.append(_above(high).map(repr))
    return st.one_of(*choices)


def bad_integer(low: int, high: int) -> st.SearchStrategy[str]:
    """Text that is no integer in [low, high]."""
    return st.one_of(
        st.integers(max_value=low - 1).map(str),
        st.integers(min_value=high + 1).map(str),
        st.floats().map(repr),  # "2.0", "nan": not integers
        _JUNK.filter(lambda text: not _parses(int, text)),
    )


def bad_name() -> st.SearchStrategy[str]:
    """A name that nothing registers (planner, simulator, scenario, controller...)."""
    return st.text(_TEXT.filter(lambda c: c != ","), max_size=8).map(lambda text: "zz" + text)


def in_list(valid: list[str], bad: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
    """A comma-separated list of valid entries with one bad entry among them (a bad entry
    must not be empty: empty entries are skipped)."""
    entry = bad.filter(lambda text: "," not in text and text.strip() != "")
    return st.tuples(st.lists(st.sampled_from(valid), max_size=3), entry, st.integers(0, 3)).map(
        lambda parts: ",".join([*parts[0][: parts[2]], parts[1], *parts[0][parts[2] :]])
    )


def empty_list() -> st.SearchStrategy[str]:
    return st.sampled_from(["", " ", ",", " , ,"])


# --------------------------------------------------------------- flags: one broken value

RUN = ["run", "--planner=hold", "--stabilizer=posture", "--sim=mujoco", "--scenario=stand"]
RUN_PUSH = ["run", "--planner=hold", "--stabilizer=posture", "--sim=mujoco"]
RUN_PUSH += ["--scenario=stand_push"]
ROBOT = ["robot", "--json"]
COMPARE = ["compare", "--planners=hold", "--sims=mujoco", "--scenario=stand"]
DEMO = ["demo", "--sim=mujoco"]
SWEEP = ["sweep", "--controllers=hold+posture", "--sims=mujoco", "--scenarios=stand"]
SWEEP += ["--out=out", "--no-progress"]
PUSH = [*SWEEP, "--push-dv=0.2"]

seconds = bad_number(CONTROL_PERIOD_S, MAX_EPISODE_SECONDS)
seed = bad_integer(0, SEED_LIMIT - 1)
scale = bad_number(*SCALE_RANGE)

# (base argv, flag, bad values, a fragment the message must hold)
FLAG_CASES: list[tuple[list[str], str, st.SearchStrategy[str], str]] = [
    (RUN, "--duration", seconds, "--duration"),
    (RUN, "--seed", seed, "--seed"),
    (RUN, "--planner", bad_name(), "planner"),
    (RUN, "--stabilizer", bad_name(), "stabilizer"),
    (RUN, "--sim", bad_name(), "simulator"),
    (RUN, "--scenario", bad_name(), "scenario"),
    (RUN, "--estimator", bad_name(), "estimator"),
    (RUN, "--push-impulse", st.just("1"), "takes no push"),  # a push in a scenario without
    (RUN_PUSH, "--push-impulse", bad_number(0.0, MAX_PUSH_IMPULSE_NS), "--push-impulse"),
    (RUN_PUSH, "--push-direction", bad_number(-math.inf, math.inf), "--push-direction"),
    (ROBOT, "--scale", scale, "--scale"),
    (ROBOT, "--mass", bad_number(*MASS_RANGE_KG), "--mass"),
    (DEMO, "--duration", seconds, "--duration"),
    (DEMO, "--scale", scale, "--scale"),
    (DEMO, "--sim", in_list(["mujoco", "pybullet"], bad_name()), "simulator"),
    (COMPARE, "--planners", in_list(["hold", "linear_mpc"], bad_name()), "planner"),
    (COMPARE, "--planners", empty_list(), "--planners"),
    (COMPARE, "--sims", in_list(["mujoco", "pybullet"], bad_name()), "simulator"),
    (COMPARE, "--stabilizer", bad_name(), "stabilizer"),
    (COMPARE, "--scenario", bad_name(), "scenario"),
    (COMPARE, "--formulations", in_list(["dense:daqp"], bad_name()), "formulation"),
    (COMPARE, "--horizons", in_list(["10", "20"], bad_integer(1, MAX_HORIZON)), "--horizons"),
    (COMPARE, "--horizons", empty_list(), "--horizons"),
    (SWEEP, "--controllers", in_list(["hold+posture", "all"], bad_name()), "controllers"),
    (SWEEP, "--controllers", empty_list(), "--controllers"),
    (SWEEP, "--sims", in_list(["mujoco", "pybullet"], bad_name()), "sims"),
    (SWEEP, "--scenarios", in_list(["stand", "walk"], bad_name()), "scenarios"),
    (SWEEP, "--seeds", in_list(["0", "7"], seed), "--seeds"),
    (SWEEP, "--scales", in_list(["1", "0.8"], scale), "--scales"),
    (SWEEP, "--frictions", in_list(["0.6"], bad_number(0.0, FRICTION_MAX, True)), "--frictions"),
    (SWEEP, "--duration", seconds, "--duration"),
    (SWEEP, "--workers", bad_integer(1, MAX_WORKERS), "--workers"),
    (
        SWEEP,
        "--name",
        st.sampled_from(["", ".", "..", "../../x", "a/b", "/tmp/x", "x..y"]),
        "--name",
    ),
    (SWEEP, "--name", _JUNK.filter(lambda t: not re.fullmatch(r"[\w.-]+", t, re.A)), "--name"),
    (SWEEP, "--push-dv", in_list(["0.2"], bad_number(0.0, MAX_PUSH_DV, True)), "--push-dv"),
    (PUSH, "--push-count", bad_integer(1, MAX_PUSH_COUNT), "--push-count"),
    (PUSH, "--push-seed", seed, "--push-seed"),
    (PUSH, "--push-phases", in_list(["standing", "walking"], bad_name()), "push.phases"),
    (SWEEP, "--timeout-base-s", bad_number(0.0, math.inf, True), "--timeout-base-s"),
]


@settings(FUZZ, max_examples=EXAMPLES["flags"])
@given(case=st.sampled_from(FLAG_CASES).flatmap(lambda c: st.tuples(st.just(c), c[2])))
def test_a_flag_with_a_bad_value_is_refused(case):
    (base_argv, flag, _, fragment), value = case
    message = refused([*base_argv, f"{flag}={value}"])
    assert fragment in message, message


# -------------------------------------------------------- the command line's structure

VALID_ARGV = {"run": RUN, "robot": ROBOT, "compare": COMPARE, "demo": DEMO, "sweep": SWEEP}
REQUIRED = {"run": RUN[1:], "compare": COMPARE[1:2], "sweep": SWEEP[1:2]}


@st.composite
def broken_command_line(draw) -> list[str]:
    command = draw(st.sampled_from(sorted(VALID_ARGV)))
    argv = list(VALID_ARGV[command])
    ways = ["unknown flag", "no value", "command"] + (["drop"] if command in REQUIRED else [])
    how = draw(st.sampled_from(ways))
    if how == "unknown flag":
        word = draw(st.text(st.characters(categories=("Ll", "Nd")), max_size=8))
        argv.insert(draw(st.integers(1, len(argv))), f"--zz{word}")
    elif how == "no value":  # a flag that takes a value given none, at the end
        flags = {"run": "--duration", "robot": "--scale", "compare": "--horizons"}
        argv.append(flags.get(command, "--duration" if command == "demo" else "--seeds"))
    elif how == "drop":  # a required flag (sweep: the spec's required controllers)
        argv.remove(draw(st.sampled_from(REQUIRED[command])))
    else:
        argv[0] = "zz" + draw(st.text(_TEXT, max_size=6))
    return argv


@settings(FUZZ, max_examples=EXAMPLES["structure"])
@given(argv=broken_command_line())
def test_a_broken_command_line_is_refused(argv):
    refused(argv)


# ----------------------------------------------------- sweep spec files: one broken field

VALID_SPEC: dict[str, Any] = {
    "controllers": ["hold+posture"],
    "sims": ["mujoco"],
    "scenarios": ["stand"],
    "duration": 0.5,
}
VALID_PUSH_SPEC: dict[str, Any] = {
    "controllers": ["hold+posture"],
    "sims": ["mujoco"],
    "push": {"dv": [0.2], "count": 2},
}

_scalar = st.one_of(
    st.text(_TEXT, max_size=6).map(lambda text: "zz" + text),
    st.integers(-(2**70), 2**70),
    st.floats(),
    st.booleans(),
)
_table = st.dictionaries(st.text("abcxyz_", min_size=1, max_size=5), _scalar, max_size=3)
_not_a_list = st.one_of(_scalar, _table)  # "zz..." strings: a bare name must be unknown


def _numbers_outside(low: float, high: float, strict: bool = False) -> st.SearchStrategy:
    """TOML values that are no number in [low, high] ((low, high] when `strict`)."""
    return st.one_of(
        st.sampled_from([math.nan, math.inf, -math.inf, 10**400, True, False, "1", [1.0]]),
        _below(low, strict),
        _above(high),
        st.integers(max_value=math.ceil(low) - 1),
        st.integers(min_value=math.floor(high) + 1),
    )


def _integers_outside(low: int, high: int) -> st.SearchStrategy:
    return st.one_of(
        st.integers(max_value=low - 1),
        st.integers(min_value=high + 1),
        st.floats(),
        st.booleans(),
        st.text(_TEXT, max_size=4),
        _table,
    )


def _list_with(valid: list, bad: st.SearchStrategy) -> st.SearchStrategy[list]:
    return st.one_of(
        st.just([]),
        _not_a_list,
        st.tuples(st.lists(st.sampled_from(valid), max_size=3), bad, st.integers(0, 3)).map(
            lambda parts: [*parts[0][: parts[2]], parts[1], *parts[0][parts[2] :]]
        ),
    )


def _names_with(valid: list[str], twice: bool = True) -> st.SearchStrategy:
    """Lists of names with one unknown or no name among them, not a list, or a name twice
    (`twice`: where that is an error; the push phases are deduplicated)."""
    unknown = st.one_of(bad_name(), st.integers(), st.booleans(), st.lists(st.just("x")))
    bad = _list_with(valid, unknown).filter(lambda value: value != [])  # [] is valid traces
    return st.one_of(bad, st.just([valid[0], valid[0]])) if twice else bad


_bad_name_value = st.one_of(
    st.sampled_from(["", ".", "..", ".hidden", "../../x", "a/b", "/abs", "x..y", "a" * 101]),
    _JUNK.filter(lambda text: not re.fullmatch(r"[\w-][\w.-]*", text, re.A)),
    st.integers(),
    st.booleans(),
    st.lists(st.just("x"), max_size=2),
)

# field -> (bad values, a fragment the message must hold)
SPEC_FIELDS: dict[str, tuple[st.SearchStrategy, str]] = {
    "name": (_bad_name_value, "'name'"),
    "controllers": (_names_with(["hold+posture", "preview_zmp+dcm"]), "'controllers'"),
    "sims": (_names_with(["mujoco", "pybullet"]), "'sims'"),
    "scenarios": (_names_with(["stand", "walk"]), "'scenarios"),
    "traces": (_names_with(["walk"]), "'traces'"),
    "seeds": (_list_with([0, 1], _integers_outside(0, SEED_LIMIT - 1)), "'seeds"),
    "scales": (_list_with([1.0, 0.8], _numbers_outside(*SCALE_RANGE)), "'scales"),
    "frictions": (_list_with([0.6], _numbers_outside(0.0, FRICTION_MAX, True)), "'frictions"),
    "estimator": (st.one_of(bad_name(), st.integers(), st.lists(st.just("x"))), "'estimator'"),
    "duration": (_numbers_outside(CONTROL_PERIOD_S, MAX_EPISODE_SECONDS), "'duration'"),
    "push": (st.one_of(_scalar, st.lists(_scalar, max_size=2)), "'push'"),
    # owned by the timeout settings: no integers beyond a float's range here
    "timeout_base_s": (
        st.sampled_from([0, -1, 0.0, -2.5, math.nan, math.inf, "60", True, [60]]),
        "'timeout_base_s'",
    ),
}
PUSH_FIELDS: dict[str, tuple[st.SearchStrategy, str]] = {
    "dv": (_list_with([0.2, 0.4], _numbers_outside(0.0, MAX_PUSH_DV, True)), "'push.dv'"),
    "phases": (_names_with(["standing", "walking"], twice=False), "'push.phases'"),
    "count": (_integers_outside(1, MAX_PUSH_COUNT), "'push.count'"),
    "seed": (_integers_outside(0, SEED_LIMIT - 1), "'push.seed'"),
    "survival_time": (
        _numbers_outside(0.0, MAX_EPISODE_SECONDS, True),
        "'push.survival_time'",
    ),
    "standing_push_time": (
        _numbers_outside(0.0, MAX_EPISODE_SECONDS),
        "'push.standing_push_time'",
    ),
    "walking_push_step": (_integers_outside(1, WALK_STEPS), "'push.walking_push_step'"),
}


@st.composite
def broken_spec(draw) -> tuple[dict, str]:
    """(a spec mapping with exactly one thing wrong, a fragment the message must hold)."""
    kind = draw(st.sampled_from(["top", "top", "push", "push", "other"]))
    if kind == "top":
        name = draw(st.sampled_from(sorted(SPEC_FIELDS)))
        values, fragment = SPEC_FIELDS[name]
        return {**VALID_SPEC, name: draw(values)}, fragment
    if kind == "push":
        name = draw(st.sampled_from(sorted(PUSH_FIELDS)))
        values, fragment = PUSH_FIELDS[name]
        push = {**VALID_PUSH_SPEC["push"], name: draw(values)}
        return {**VALID_PUSH_SPEC, "push": push}, fragment
    how = draw(
        st.sampled_from(
            ["unknown", "unknown push", "missing", "no dv", "too long", "walking", "too many"]
        )
    )
    key = "zz" + draw(st.text("abcxyz_", max_size=5))
    if how == "unknown":
        return {**VALID_SPEC, key: draw(_scalar)}, f"unknown field {key!r}"
    if how == "unknown push":
        push = {**VALID_PUSH_SPEC["push"], key: draw(_scalar)}
        return {**VALID_PUSH_SPEC, "push": push}, f"'push.{key}' is unknown"
    if how == "missing":
        field = draw(st.sampled_from(["controllers", "sims"]))
        return {k: v for k, v in VALID_SPEC.items() if k != field}, f"missing field {field!r}"
    if how == "no dv":
        return {**VALID_PUSH_SPEC, "push": {"count": 2}}, "'push.dv' is missing"
    if how == "too long":  # each valid, together longer than an episode may be
        start = draw(st.floats(0.0, MAX_EPISODE_SECONDS - 0.2))
        survival = draw(
            st.floats(MAX_EPISODE_SECONDS - 0.1 - start, MAX_EPISODE_SECONDS).filter(
                lambda s: start + 0.1 + s > MAX_EPISODE_SECONDS and s > 0
            )
        )
        push = {"dv": [0.2], "standing_push_time": start, "survival_time": survival}
        return {**VALID_PUSH_SPEC, "push": push}, "'push.survival_time'"
    if how == "walking":  # fits standing (1.6 s + survival) but not the walk's ~3 s start
        standing = PushProtocol(dv=(0.2,)).standing_push_time + 0.1
        survival = draw(st.floats(597.0, MAX_EPISODE_SECONDS - standing - 0.01))
        push = {"dv": [0.2], "phases": ["walking"], "survival_time": survival}
        return {**VALID_PUSH_SPEC, "push": push}, "a walking push at scale 1"
    levels = draw(st.integers(101, 300))  # levels x count > MAX_EPISODES
    count = draw(st.integers(MAX_EPISODES // levels + 1, MAX_PUSH_COUNT))
    push = {"dv": [0.1 + k / 1000 for k in range(levels)], "count": count}
    return {**VALID_PUSH_SPEC, "push": push}, "episodes (controllers x sims"


def toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        return ("inf" if value > 0 else "-inf") if math.isinf(value) else repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    pairs = (f"{json.dumps(k)} = {toml_value(v)}" for k, v in value.items())
    return "{" + ", ".join(pairs) + "}"


def toml_document(data: dict[str, Any]) -> bytes:
    return "".join(f"{json.dumps(k)} = {toml_value(v)}\n" for k, v in data.items()).encode()


def test_the_toml_writer_round_trips():
    import tomllib

    data = {**VALID_PUSH_SPEC, "name": 'a "b"\\', "x": [1.5e300, -0.0, 2**70], "y": {"k": True}}
    assert tomllib.loads(toml_document(data).decode()) == data


def test_at_least_a_thousand_bad_inputs_per_run():
    assert sum(EXAMPLES.values()) >= 1000


@settings(FUZZ, max_examples=EXAMPLES["spec"])
@given(case=broken_spec(), with_flag=st.booleans())
def test_a_spec_with_one_broken_field_is_refused(case, with_flag):
    data, fragment = case
    argv = ["sweep", "--spec", "spec.toml", "--out", "out"]
    if with_flag:  # a flag that changes nothing wrong: the spec's error still shows
        argv.append("--no-progress")
    message = refused(argv, {"spec.toml": toml_document(data)})
    assert message.startswith("sweep spec"), message
    assert fragment in message, message


# ------------------------------------------------------------ files that are no spec

SPEC_TEXT = 'controllers = ["hold+posture"]\nsims = ["mujoco"]\nscenarios = ["stand"]\n'


@st.composite
def not_a_spec_file(draw) -> tuple[str, dict[str, bytes | None], str]:
    """(--spec path, files to make, a fragment the message must hold)."""
    ways = ["bytes", "text", "truncated", "folder", "missing", "empty", "device"]
    how = draw(st.sampled_from(ways))
    if how == "bytes":
        content = draw(st.binary(max_size=200))
        return "spec.toml", {"spec.toml": content}, "sweep spec"
    if how == "text":
        content = draw(st.text(max_size=200)).encode("utf-8", "surrogatepass")
        return "spec.toml", {"spec.toml": content}, "sweep spec"
    if how == "truncated":  # never the closing bracket of the last field: invalid or partial
        cut = draw(st.integers(0, len(SPEC_TEXT) - 2))
        return "spec.toml", {"spec.toml": SPEC_TEXT[:cut].encode()}, "sweep spec"
    if how == "folder":
        return "spec.toml", {"spec.toml": None}, "is a directory"
    if how == "missing":
        name = "zz" + draw(st.text("abc123", max_size=6)) + ".toml"
        return name, {}, "does not exist"
    if how == "device":  # exists, is read by nobody: no regular file
        return "/dev/null", {}, "sweep spec /dev/null is not a regular file"
    return "spec.toml", {"spec.toml": b""}, "missing field 'controllers'"


@settings(FUZZ, max_examples=EXAMPLES["toml"])
@given(case=not_a_spec_file())
def test_a_file_that_is_no_spec_is_refused(case):
    path, files, fragment = case
    message = refused(["sweep", "--spec", path, "--out", "out"], files)
    assert fragment in message, message


# ------------------------------------------------------------------------------- report

_json = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False) | st.text(max_size=5),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=5), inner),
    max_leaves=8,
)


@st.composite
def bad_report(draw) -> tuple[list[str], dict[str, bytes | None]]:
    """A results folder with no readable episode, and maybe a bad --benchmark-json."""
    results = draw(st.sampled_from(["missing", "file", "empty", "junk"]))
    files: dict[str, bytes | None] = {
        "missing": {},
        "file": {"results": b"not a folder"},
        "empty": {"results": None},
        "junk": {"results/episodes/x.parquet": draw(st.binary(max_size=64))},
    }[results]
    argv = ["report", "results", "--out", "report"]
    benchmark = draw(st.sampled_from(["none", "json", "bytes", "folder", "missing"]))
    if benchmark == "json":
        files["bench.json"] = json.dumps(draw(_json)).encode()
    elif benchmark == "bytes":
        files["bench.json"] = draw(st.binary(max_size=64))
    elif benchmark == "folder":
        files["bench.json"] = None
    if benchmark != "none":
        argv += ["--benchmark-json", "bench.json"]
    return argv, files


@settings(FUZZ, max_examples=EXAMPLES["report"])
@given(case=bad_report())
def test_a_report_of_bad_input_is_refused(case):
    argv, files = case
    message = refused(argv, files)
    assert "benchmark file bench.json" in message or "results" in message, message
