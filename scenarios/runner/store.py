"""The results store: an SQLite file written only by the calling process, WAL journal,
``synchronous=FULL``, one transaction per finished seed.

:func:`connect_db` opens any results database (the bench's schema, :data:`SCHEMA`, or the
units runner's, :mod:`gyrobench.scenarios.runner.unit_store`). :func:`start_session` and
:func:`record_seed` are the bench's reads and writes: a campaign's finished seeds are read
back on a rerun, so a campaign killed at any moment (even SIGKILL) resumes where it stopped.

Every stored seed carries a checksum (:func:`seed_checksum`: HMAC-SHA256, keyed with the
database's own key, of the campaign id, the seed, the scores' text and the failure reason) in
``seed_checksums``, written in the same transaction. The key is 32 random bytes in a file
beside the database (``<db>.key``, mode 0600, created with it: :func:`db_key`). A resume
verifies it: a row edited in the file (a score set to ``"nan"``), a corrupted one, one written
before checksums existed, or a forged one whose checksum was recomputed without the key, is
deleted with a warning and its seed recomputed, never served and never silently dropped from
the summary. Whoever can read the key file (the same user, the compensator's own process) can
still forge a row: the checksum guards against accidents and against edits by anyone without
the key, not against the user's own code.

What a campaign's compensator read (:mod:`~gyrobench.scenarios.bench.sandbox`: modules, files,
environment variables) is kept per campaign in ``campaign_reads``, with its fingerprints;
:func:`campaign_generation` picks, among the stored campaigns of one static identity, the one
whose reads are unchanged, or starts a new one.

The schema, the connection, the key file and the refusal of a foreign file are
:mod:`gyrobench.scenarios.runner.store_db`; this module holds the rows' reads and writes. The
names of both are importable from here.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import sqlite3
import time
import warnings
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from gyrobench.scenarios.cli import exits
from gyrobench.scenarios.runner.store_db import (
    DEFAULT_DB,
    KEY_BYTES,
    SCHEMA,
    KeyedConnection,
    check_database,
    check_output_file,
    connect_db,
    database_tables,
    db_key,
    key_path,
)

__all__ = [
    "DEFAULT_DB",
    "KEY_BYTES",
    "SCHEMA",
    "KeyedConnection",
    "campaign_generation",
    "db_key",
    "key_path",
    "record_reads",
    "Session",
    "check_database",
    "check_output_file",
    "database_tables",
    "connect_db",
    "dumps_scores",
    "loads_scores",
    "record_seed",
    "seed_checksum",
    "start_session",
]

def dumps_scores(scores: Mapping[str, float]) -> str:
    """One seed's scores as the JSON text the store keeps (keys sorted).

    JSON floats round-trip exactly (repr); NaN and inf are stored as strings so the text
    stays valid JSON (:func:`loads_scores` reads them back).

    Parameters
    ----------
    scores : mapping of str to float
        One seed's scores.

    Returns
    -------
    str
        JSON text, keys sorted, NaN and inf as strings.
    """
    return json.dumps(
        {k: (v if math.isfinite(v) else repr(v)) for k, v in scores.items()}, sort_keys=True
    )


def loads_scores(text: str) -> dict[str, float]:
    """The scores stored by :func:`dumps_scores`, as floats.

    Parameters
    ----------
    text : str
        JSON text written by :func:`dumps_scores`.

    Returns
    -------
    dict of str to float
        The scores.
    """
    return {k: float(v) for k, v in json.loads(text).items()}


def seed_checksum(campaign_id: str, seed: int, scores_text: str, failure: str | None, key: bytes = b"") -> str:
    """The checksum (hex) of one stored seed.

    Checksum (hex) of one stored seed: campaign id, seed, scores text and failure reason;
    HMAC-SHA256 with ``key`` (the database's, :func:`db_key`), SHA-256 without one.

    Parameters
    ----------
    campaign_id : str
        The campaign.
    seed : int
        The seed.
    scores_text : str
        Its scores as stored (:func:`dumps_scores`).
    failure : str or None
        Its failure reason.
    key : bytes
        The database's key (:func:`db_key`); empty: plain SHA-256.

    Returns
    -------
    str
        Hexadecimal HMAC-SHA256 (SHA-256 without a key).
    """
    import hmac

    doc = json.dumps([campaign_id, int(seed), scores_text, failure], separators=(",", ":")).encode("utf-8")
    if key:
        return hmac.new(key, doc, hashlib.sha256).hexdigest()
    return hashlib.sha256(doc).hexdigest()


def _verified(conn: sqlite3.Connection, campaign_id: str, wanted: set[int]) -> tuple[dict, dict]:
    """The stored seeds among ``wanted`` whose checksum holds (scores, failures); the others are
    deleted (inside the caller's transaction) with one warning naming them, so they are recomputed."""
    failures = dict(conn.execute("SELECT seed, reason FROM seed_failures WHERE campaign_id = ?", (campaign_id,)))
    sums = dict(conn.execute("SELECT seed, sha256 FROM seed_checksums WHERE campaign_id = ?", (campaign_id,)))
    done: dict[int, dict[str, float]] = {}
    bad: list[int] = []
    for seed, text in conn.execute("SELECT seed, scores FROM seed_scores WHERE campaign_id = ?", (campaign_id,)):
        if seed not in wanted:
            continue
        ok = isinstance(text, str) and sums.get(seed) == seed_checksum(
            campaign_id, seed, text, failures.get(seed), getattr(conn, "key", b"")
        )
        try:
            scores = loads_scores(text) if ok else None
        except (ValueError, TypeError, AttributeError):
            scores = None
        if scores is None:
            bad.append(seed)
        else:
            done[seed] = scores
    for seed in bad:
        for table in ("seed_scores", "seed_failures", "seed_checksums"):
            conn.execute(f"DELETE FROM {table} WHERE campaign_id = ? AND seed = ?", (campaign_id, seed))
    if bad:
        warnings.warn(
            f"campaign {campaign_id}: the stored scores of seed(s) {', '.join(map(str, sorted(bad)))} do not match "
            "their checksum (edited, forged, corrupted or stored by an older gyrobench); recomputing them",
            RuntimeWarning,
            stacklevel=3,
        )
    return done, {s: r for s, r in failures.items() if s in done}


@dataclass(frozen=True, slots=True, kw_only=True)
class Session:
    """One run of a campaign on a database: its session row and the seeds already stored.

    ``done`` maps each requested seed found in the database to its scores (as stored);
    ``failed`` maps those of them that failed to why.

    Parameters
    ----------
    session_id : int
        The session's row id.
    done : mapping of int to mapping of str to float
        Each requested seed already stored -> its scores.
    failed : mapping of int to str
        The stored seeds that failed -> why.
    """

    session_id: int
    done: Mapping[int, Mapping[str, float]]
    failed: Mapping[int, str]


def start_session(
    conn: sqlite3.Connection,
    campaign_id: str,
    seeds: Iterable[int],
    *,
    scenario: str,
    compensator: str,
    config: str,
    identity: str,
) -> Session:
    """Register a campaign, read back its stored seeds and open a session, in one transaction.

    Register the campaign (once), read back its stored seeds among ``seeds`` and open a
    session, in one transaction.

    Parameters
    ----------
    conn : sqlite3.Connection
        The open results database.
    campaign_id : str
        The campaign.
    seeds : iterable of int
        The seeds requested.
    scenario : str
        The scenario's name.
    compensator : str
        The compensator's ``"module:attr"`` name.
    config : str
        The configuration's JSON identity.
    identity : str
        The compensator's code identity.

    Returns
    -------
    Session
        The session and the requested seeds already stored.
    """
    seeds = tuple(seeds)
    conn.execute("BEGIN IMMEDIATE")
    try:
        conn.execute(
            "INSERT OR IGNORE INTO campaigns VALUES (?, ?, ?, ?, ?, ?)",
            (campaign_id, scenario, compensator, config, identity, time.time()),
        )
        done, failed = _verified(conn, campaign_id, set(seeds))
        cur = conn.execute(
            "INSERT INTO sessions (campaign_id, started, n_requested, n_reused, pid) "
            "VALUES (?, ?, ?, ?, ?)",
            (campaign_id, time.time(), len(seeds), len(done), os.getpid()),
        )
        session_id = int(cur.lastrowid or 0)
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    conn.execute("COMMIT")
    return Session(session_id=session_id, done=done, failed=failed)


def record_seed(
    conn: sqlite3.Connection,
    campaign_id: str,
    session_id: int,
    seed: int,
    scores: Mapping[str, float],
    elapsed: float,
    failure: str | None,
    *,
    db: str,
) -> tuple[dict[str, float], str | None]:
    """Commit one finished seed and return it as a resume reads it back.

    Commit one finished seed; return its scores exactly as a resume reads them back, and
    why it failed (None if it did not).

    Another process running the same campaign on the same file may have stored the seed
    meanwhile: scores are deterministic, so it must be the same, else
    :class:`~gyrobench.scenarios.cli.exits.InternalError` (``db`` names the file).

    Parameters
    ----------
    conn : sqlite3.Connection
        The open results database.
    campaign_id : str
        The campaign.
    session_id : int
        The session that computed the seed.
    seed : int
        The seed.
    scores : mapping of str to float
        Its scores.
    elapsed : float
        Its run time [s].
    failure : str or None
        Why it failed (None: it did not).
    db : str
        The database's name, for the message.

    Returns
    -------
    tuple of (dict of str to float, str or None)
        The stored scores and failure reason.
    """
    text = dumps_scores(scores)
    conn.execute("BEGIN IMMEDIATE")
    try:
        conn.execute(
            "INSERT INTO seed_scores "
            "(campaign_id, seed, scores, elapsed_s, finished, session_id) "
            "VALUES (?, ?, ?, ?, ?, ?)",
            (campaign_id, seed, text, elapsed, time.time(), session_id),
        )
        if failure is not None:
            conn.execute(
                "INSERT INTO seed_failures (campaign_id, seed, reason) VALUES (?, ?, ?)",
                (campaign_id, seed, failure),
            )
        conn.execute(
            "INSERT INTO seed_checksums (campaign_id, seed, sha256) VALUES (?, ?, ?)",
            (campaign_id, seed, seed_checksum(campaign_id, seed, text, failure, getattr(conn, "key", b""))),
        )
    except sqlite3.IntegrityError:
        conn.execute("ROLLBACK")
        (other,) = conn.execute(
            "SELECT scores FROM seed_scores WHERE campaign_id = ? AND seed = ?", (campaign_id, seed)
        ).fetchone()
        if other != text:
            raise exits.InternalError(
                f"seed {seed} of campaign {campaign_id} gave different scores in two runs on "
                f"db {db!r}: the scenario or compensator is not deterministic "
                "(it must give the same scores for the same seed)"
            ) from None
        row = conn.execute(
            "SELECT reason FROM seed_failures WHERE campaign_id = ? AND seed = ?",
            (campaign_id, seed),
        ).fetchone()
        failure = row[0] if row else failure
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    else:
        conn.execute("COMMIT")
    return loads_scores(text), failure


# ----------------------------------------------------------------------------- what a campaign read
def campaign_generation(
    conn: sqlite3.Connection, static_id: str, fingerprint: Any
) -> tuple[str, dict[str, Any]]:
    """The campaign id a run of ``static_id`` continues, or a new generation's.

    The campaign of ``static_id`` whose recorded reads still fingerprint the same (``fingerprint``
    maps the stored read names to their fingerprints now), newest first; else a new one: its id
    is ``static_id`` for the first, ``static_id`` hashed with its generation number after.
    Returns (campaign id, the read names recorded for it, empty for a new one).

    Parameters
    ----------
    conn : sqlite3.Connection
        The open results database.
    static_id : str
        The campaign's static id (scenario, compensator, config, identity).
    fingerprint : callable or mapping
        Maps the stored read names to their fingerprints now.

    Returns
    -------
    tuple of (str, dict)
        (campaign id, the read names recorded for it; empty for a new one).
    """
    rows = conn.execute(
        "SELECT campaign_id, generation, names, fingerprint FROM campaign_reads WHERE static_id = ? "
        "ORDER BY generation DESC",
        (static_id,),
    ).fetchall()
    for cid, _gen, names_text, stored in rows:
        try:
            names = json.loads(names_text)
            if fingerprint(names) == json.loads(stored):
                return str(cid), names
        except (ValueError, TypeError):
            continue
    if not rows:
        return static_id, {}
    gen = 1 + max(int(r[1]) for r in rows)
    return hashlib.sha256(f"{static_id}/{gen}".encode()).hexdigest()[:16], {}


def record_reads(
    conn: sqlite3.Connection, campaign_id: str, static_id: str, names: Mapping[str, Any], fingerprint: Mapping[str, str]
) -> None:
    """Store (or replace) what campaign ``campaign_id`` read, with its fingerprints, in one transaction.

    Parameters
    ----------
    conn : sqlite3.Connection
        The open results database.
    campaign_id : str
        The campaign.
    static_id : str
        Its static id.
    names : mapping of str to object
        The read names and what each read.
    fingerprint : mapping of str to str
        Each read name's fingerprint.
    """
    conn.execute("BEGIN IMMEDIATE")
    try:
        row = conn.execute("SELECT generation FROM campaign_reads WHERE campaign_id = ?", (campaign_id,)).fetchone()
        if row is None:
            (gen,) = conn.execute(
                "SELECT COALESCE(MAX(generation) + 1, 0) FROM campaign_reads WHERE static_id = ?", (static_id,)
            ).fetchone()
        else:
            gen = row[0]
        conn.execute(
            "INSERT OR REPLACE INTO campaign_reads VALUES (?, ?, ?, ?, ?)",
            (campaign_id, static_id, int(gen), json.dumps(dict(names), sort_keys=True),
             json.dumps(dict(fingerprint), sort_keys=True)),
        )
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    conn.execute("COMMIT")
