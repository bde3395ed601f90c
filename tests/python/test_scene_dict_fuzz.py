"""Fuzz test of the Python scene-dict path (contact.scene_from_dict): a fixed
seed mutates the example scenes' dicts - values replaced by other types, NaN, +-inf, huge or
negative numbers, deep nesting, keys deleted or unknown ones added - and every case must
either build a Scene or be refused with contact.SceneError or ValueError (the documented
errors). Any other exception, or a crash of the interpreter, is a finding. The C++ reader
behind it is fuzzed with coverage guidance by tests/fuzz/libfuzzer/fuzz_scene.cpp."""
import copy
import os
import random
import tomllib

import pytest

import contact

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = os.path.join(HERE, "..", "..", "examples")
SCENES = [os.path.join(EXAMPLES, "scenes", "block_drop_2d.toml"),
          os.path.join(EXAMPLES, "thesis", "friction_2d_flat.toml"),
          os.path.join(EXAMPLES, "validation", "incline.toml")]
CASES = 150  # per scene; each case is one scene_from_dict call (no run)
VALUES = [float("nan"), float("inf"), -float("inf"), 1e308, -1e308, 0, -1, 0.0, -0.0, 2**63,
          -2**63 - 1, 10**30, True, False, "", "x" * 1000, "\x00", "nan", [], [1, 2, 3],
          [[1.0]] * 3, {"a": 1}, {}, None, b"bytes", 1 + 2j, object()]


def paths(d, prefix=()):
    for key, value in d.items():
        yield prefix + (key,)
        if isinstance(value, dict):
            yield from paths(value, prefix + (key,))


def mutate(rng, scene):
    d = copy.deepcopy(scene)
    for _ in range(rng.randint(1, 3)):
        path = rng.choice(list(paths(d)))
        parent = d
        for key in path[:-1]:
            parent = parent[key]
        kind = rng.choice(["value", "value", "delete", "unknown", "nest", "scale"])
        if kind == "value":
            parent[path[-1]] = rng.choice(VALUES)
        elif kind == "delete":
            del parent[path[-1]]
        elif kind == "unknown":
            parent["no_such_key_" + str(rng.randint(0, 9))] = rng.choice(VALUES[:8])
        elif kind == "nest":
            value = 1.0
            for _ in range(rng.randint(1, 200)):
                value = [value]
            parent[path[-1]] = value
        elif isinstance(parent[path[-1]], (int, float)) and not isinstance(parent[path[-1]], bool):
            parent[path[-1]] = parent[path[-1]] * rng.choice([-1, 0, 1e-300, 1e300])
    return d


@pytest.mark.parametrize("scene_path", SCENES, ids=os.path.basename)
def test_mutated_scene_dicts_build_or_are_refused(scene_path):
    with open(scene_path, "rb") as f:
        scene = tomllib.load(f)
    base_dir = os.path.dirname(scene_path)
    contact.scene_from_dict(scene, base_dir=base_dir)  # the unmutated dict builds
    rng = random.Random(32)
    outcomes = {"built": 0, "refused": 0}
    for case in range(CASES):
        d = mutate(rng, scene)
        try:
            contact.scene_from_dict(d, base_dir=base_dir)
            outcomes["built"] += 1
        except (contact.SceneError, ValueError) as e:
            assert str(e), f"case {case}: an empty message for {d}"
            outcomes["refused"] += 1
    assert outcomes["refused"] > 0, outcomes  # the mutations do reach the checks
