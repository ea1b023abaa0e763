"""``gyrobench bench --part FILE.toml|NAME``: the user's own part as the bench scenario ``part``.

The part file is read here, once, checked (one line naming the file and the key, exit 2) and put
into the scenario's configuration as its text (:mod:`gyrobench.scenarios.part_bench`), so the
campaign's identity includes the file's content and the workers never read the file.
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
from typing import Any

__all__ = ["check_same_part", "part_config", "part_line"]


def part_config(args: argparse.Namespace, config: Any) -> Any:
    """``config`` with ``--part`` (a file's text or a built-in name) and ``--model`` put in.

    Parameters
    ----------
    args : argparse.Namespace
        The ``bench`` arguments (``part``, ``model``).
    config : gyrobench.scenarios.part_bench.Config
        The scenario's configuration (its default or ``--config``).

    Returns
    -------
    gyrobench.scenarios.part_bench.Config
        With ``part``/``part_toml`` and ``model`` set.

    Raises
    ------
    ValueError
        One line: ``--model`` without the part scenario, a missing or non-UTF-8 file, a bad part
        file, an unknown part, or a sheet the physics model cannot take.
    """
    from gyrobench.scenarios import part_bench
    from gyrobench.scenarios.cli.common import input_file
    from gyrobench.sim import parts

    if not isinstance(config, part_bench.Config):
        raise ValueError("--model goes with --part (the scenario 'part'); other scenarios set their model in --config")
    changes: dict[str, Any] = {}
    if args.part is not None:
        if args.part.lower().endswith(".toml"):
            path = input_file(args.part, "--part")
            try:
                text = path.read_bytes().decode("utf-8")
            except UnicodeDecodeError as exc:
                raise ValueError(f"--part {args.part!r} is not UTF-8 text: {exc}") from None
            except OSError as exc:
                raise ValueError(f"--part {args.part!r} cannot be read: {exc.strerror or exc}") from None
            parts.loads_toml(text, source=f"--part {args.part!r}")  # one line naming the file and the key
            changes.update(part="file", part_toml=text)
        else:
            try:
                changes.update(part=parts.get(args.part).datasheet.name, part_toml="")
            except ValueError as exc:
                raise ValueError(f"--part: {exc}") from None
    if args.model is not None:
        changes["model"] = args.model
    config = dataclasses.replace(config, **changes)
    if part_bench.model_of(config) == "physics":
        part = part_bench.part_of(config)
        try:
            parts.physics_spec(part.datasheet)
        except ValueError as exc:
            raise ValueError(f"--part {args.part or config.part!r} --model physics: {exc} (--model budget runs the "
                             "datasheet budget)") from None
    return config


def check_same_part(baseline: Any, config: Any, path: str) -> None:
    """Refuse a ``--baseline`` of another part or model: a paired comparison needs the same units.

    Parameters
    ----------
    baseline : Campaign
        The loaded baseline (its ``config`` is the configuration's repr).
    config : gyrobench.scenarios.part_bench.Config
        This campaign's configuration.
    path : str
        The baseline file, for the message.

    Raises
    ------
    ValueError
        If the baseline was run on another part file, built-in part or model.
    """
    needle = f"part={config.part!r}, part_toml={config.part_toml!r}, model={config.model!r}"
    if needle not in str(baseline.config):
        raise ValueError(f"--baseline {path!r} was run on another part or model than this campaign's "
                         f"({_label(config)}, model {config.model}); a paired comparison needs the same part")


def _label(config: Any) -> str:
    if config.part != "file":
        return f"built-in part {config.part}"
    digest = hashlib.sha256(config.part_toml.encode("utf-8")).hexdigest()[:12]
    return f"part file sha256 {digest}"


def part_line(config: Any, given: str | None) -> str:
    """The line the bench prints first: which part, from where, on which model, and the two programs.

    Parameters
    ----------
    config : gyrobench.scenarios.part_bench.Config
        The configuration.
    given : str or None
        ``--part`` as given.

    Returns
    -------
    str
        One line.
    """
    from gyrobench.scenarios import part_bench
    from gyrobench.sim import parts

    ds = part_bench.part_of(config).datasheet
    where = f" from {given} ({_label(config)})" if config.part == "file" else " (built in)"
    kind = part_bench.model_of(config)
    model = parts.physics_summary(ds) if kind == "physics" else "the datasheet budget"
    train, test = config.train_temperatures_c, config.test_temperatures_c
    return (f"part {ds.name}{where}; model {kind}: {model}; calibrated in "
            f"{config.train_duration_s:g} s over {min(train):g}..{max(train):g} degC, scored on a held-out "
            f"{config.test_duration_s:g} s program over {min(test):g}..{max(test):g} degC at {config.fs_hz:g} Hz")
