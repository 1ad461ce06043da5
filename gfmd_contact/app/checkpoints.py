"""Checkpoints of a run: partial/, written as the load steps go and read back to continue a run.

While a run goes, every realization writes into partial/ (`save_step`): realization<i>.csv (its
rows, appended), realization<i>_step<k>.npz (saved fields, and the warm start after that step) and
realization<i>.state.npz (the `gfmd_contact.core.loading.RampState` warm start, messages, reasons, notes;
"done" once the realization ends), at the first step, at every saved step, and otherwise once
CHECKPOINT_SECONDS have passed since the last write; the steps in between are written when the
ramp stops, however it stops (`checkpointing`: an interrupt, an error, the end), so only a kill
that gives no chance (SIGKILL, a power cut) loses them, at most CHECKPOINT_SECONDS of work and
the step under way. `load_part` reads them back to continue an interrupted run (`gfmd run --resume`),
repairing damage rather than refusing it. Every file is written to a temporary name and
renamed (a CSV row is appended and flushed), so an interrupt never leaves a half-written
result; files get the permissions of the process umask. Here too the write primitives every
run file uses (`_atomic_write`, `_npz_bytes`, `_fmt`: a number as the CSV files hold it).
"""

from __future__ import annotations

import io
import json
import math
import os
import threading
import time
import zipfile
import zlib
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from gfmd_contact.core import surfaces
from gfmd_contact.core.ramp import y_positions
from gfmd_contact.core.result import CURVE_COLUMNS, FIELD_NAMES, Result

from . import safe_files

PARTIAL = "partial"
#: wall seconds between two checkpoints of a realization (`save_step`) but at its first and its saved steps
#: ($GFMD_CHECKPOINT_SECONDS where set, `checkpoint_seconds`; 0: every step). One every step cost 16–18 % of a
#: weak-adhesion or hard-wall study task's CPU at N = 2^17 and wrote 2.2 MB a step per task directory (the warm start's
#: two spectra; 83 GB in the sensitivity study's 33 min): docs/design/performance.md
CHECKPOINT_SECONDS = 2.0


@dataclass
class _Written:
    """What this process wrote of one realization's partial files: when, how many CSV rows (None: not known), and
    the checkpoint `save_step` deferred ((out, result, state, message counts) or None)."""

    time: float = -math.inf
    rows: int | None = None
    deferred: tuple | None = None


#: per realization's state file path (`_key`): its `_Written`
_WRITTEN = {}
_LOCK = threading.Lock()
_clock = time.monotonic  # the checkpoints' clock (a test's to set)


def _file_mode():
    return safe_files.file_mode()


def _atomic_write(path, data, binary=False):
    safe_files.atomic_write(path, data, binary=binary)


#: a saved .npz deflates an array only where zlib shrinks its first COMPRESS_PROBE bytes to less than COMPRESS_WORTH of
#: them (`_worth_deflating`): float fields hardly compress (0.83–0.95 of their size at N = 2^17) and deflating them
#: cost 1.6 CPU s of a 15 s study task there (docs/design/performance.md); zeros (u_x, t_t of a normal-only
#: law), constants and masks shrink to almost nothing
COMPRESS_PROBE = 1 << 16
COMPRESS_WORTH = 0.5
#: every member's zip timestamp: the same arrays give the same bytes
ZIP_DATE = (1980, 1, 1, 0, 0, 0)


def _worth_deflating(a):
    """Whether zlib (level 1) shrinks the first COMPRESS_PROBE bytes of array `a` below COMPRESS_WORTH of them."""
    flat = a.reshape(-1)
    head = np.ascontiguousarray(flat[:max(COMPRESS_PROBE // max(a.itemsize, 1), 1)]).tobytes()
    return bool(head) and len(zlib.compress(head, 1)) < COMPRESS_WORTH * len(head)


def _npz_bytes(arrays, compress=True):
    """The .npz file of `arrays` as bytes (`np.load` reads it). compress=True deflates the arrays worth it
    (`_worth_deflating`), the others are stored; compress=False stores every array (the per-step warm-start state:
    float spectra hardly compress, and zlib cost 24 % of a hard-wall study task at N = 2^17)."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", allowZip64=True) as zf:
        for name, value in arrays.items():
            a = np.asanyarray(value)
            info = zipfile.ZipInfo(f"{name}.npy", date_time=ZIP_DATE)
            info.compress_type = zipfile.ZIP_DEFLATED if compress and _worth_deflating(a) else zipfile.ZIP_STORED
            with zf.open(info, "w", force_zip64=True) as fh:
                np.lib.format.write_array(fh, a, allow_pickle=False)
    return buf.getvalue()


def _fmt(v):
    if isinstance(v, (float, np.floating)):
        return repr(float(v))
    return str(int(v)) if isinstance(v, (bool, np.bool_, int, np.integer)) else str(v)


def _part(out, realization, suffix):
    return Path(out) / PARTIAL / f"realization{realization}{suffix}"


def _save_state(out, result, state, done, counts=None):
    """The state file; `counts` (messages, reasons, notes): how many of each belong to state.step (all if None)."""
    n_messages, n_reasons, n_notes = counts or (len(result.messages), len(result.reasons), len(result.notes))
    arrays = {"step": np.int64(state.step), "done": np.bool_(done), "slip_warned": np.bool_(state.slip_warned),
              "text": np.array(json.dumps({"method": result.method, "model": result.model,
                                           "reasons": list(result.reasons)[:n_reasons],
                                           "messages": list(result.messages)[:n_messages],
                                           "notes": list(result.notes)[:n_notes],
                                           "fallback_steps": list(result.diagnostics.get("fallback_steps", [])),
                                           "algorithms": list(result.diagnostics.get("algorithms", [])),
                                           "instabilities": list(result.diagnostics.get("instabilities", []))}))}
    if not done:
        arrays.update(current=state.current, previous=state.previous)
    _atomic_write(_part(out, result.realization, ".state.npz"), _npz_bytes(arrays, compress=False),
                  binary=True)


def _save_fields(out, result, k, state=None):
    """Step k's saved fields, and the method's per-step diagnostics of that step (diag_<name>); with the
    ramp's `state` after step k, also its warm start (ramp_current, ramp_previous, ramp_slip_warned) and
    the counts of messages, reasons and notes then (ramp_counts): what `load_part` continues from when
    the CSV's consistent rows end before the saved step."""
    arrays = dict(result.fields[k])
    arrays.update({f"diag_{name}": per_step[k] for name, per_step in result.diagnostics.items()
                   if isinstance(per_step, dict) and k in per_step})
    if state is not None and state.current is not None:
        arrays.update(ramp_current=state.current, ramp_previous=state.previous,
                      ramp_slip_warned=np.bool_(state.slip_warned),
                      ramp_counts=np.array([len(result.messages), len(result.reasons), len(result.notes)]))
    _atomic_write(_part(out, result.realization, f"_step{k}.npz"), _npz_bytes(arrays), binary=True)


def checkpoint_seconds():
    """The seconds between checkpoints: $GFMD_CHECKPOINT_SECONDS where set, else CHECKPOINT_SECONDS; a value that
    is not a number of seconds ≥ 0 is a ValueError naming the variable."""
    text = os.environ.get("GFMD_CHECKPOINT_SECONDS")
    if text is None:
        return CHECKPOINT_SECONDS
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not 0 <= value < math.inf:
        raise ValueError(f"GFMD_CHECKPOINT_SECONDS = {text!r}: expected the seconds between two checkpoints of a "
                         "realization, a number ≥ 0 (0: every load step; unset: "
                         f"{CHECKPOINT_SECONDS:g})")
    return value


def _key(out, realization):
    return str(Path(out, PARTIAL, f"realization{realization}.state.npz").absolute())


def save_step(out, result, state):
    """Checkpoint (gfmd.loading.run_realization): put step state.step of `result` on disk, or defer it.

    Written at the realization's first step, at a saved step (its fields) and once CHECKPOINT_SECONDS
    have passed since the last write; otherwise the step is kept in memory (its warm start, the message
    counts) for the next write or `checkpointing`'s. A write: the CSV rows since the last write
    (appended, flushed), the step's fields if saved, then the state; `load_part` trusts a row only up
    to the state's step, so a kill between any two writes loses at most the rows since the last state.
    A saved step's fields file also keeps the warm start after it, so rows lost before the state's step
    cost only the steps after the last saved one (a second, rotating state file instead would write
    the state twice every step: +66 kB a step at N = 4096, against +64 kB per saved step here, measured).
    """
    from gfmd_contact.core.loading import RampState

    key = _key(out, result.realization)
    deferred = (out, result, RampState(step=state.step, current=state.current, previous=state.previous,
                                       slip_warned=state.slip_warned),
                (len(result.messages), len(result.reasons), len(result.notes)))
    with _LOCK:
        entry = _WRITTEN.setdefault(key, _Written())
        due = state.step in result.fields or not _clock() - entry.time < checkpoint_seconds()
        entry.deferred = None if due else deferred
    if due:
        _write_step(key, *deferred)


def _write_step(key, out, result, state, counts):
    k = state.step
    entry = _WRITTEN.setdefault(key, _Written())
    path = _part(out, result.realization, ".csv")
    if entry.rows is None:  # rows on disk not known (no `start_part` in this process): the file's complete lines
        entry.rows = max(path.read_text().count("\n") - 1, 0) if path.is_file() else 0
    rows = [",".join(_fmt(result.curve[c][j]) for c in CURVE_COLUMNS) for j in range(entry.rows, k + 1)]
    if rows:
        safe_files.append_line(path, "\n".join(rows), header=",".join(CURVE_COLUMNS))
    if k in result.fields:
        _save_fields(out, result, k, state)
    _save_state(out, result, state, done=False, counts=counts)
    entry.time, entry.rows = _clock(), k + 1


def flush_steps(outs):
    """Write the checkpoints `save_step` deferred in the run directories `outs`."""
    for out in outs:
        prefix = str(Path(out, PARTIAL).absolute()) + "/"
        with _LOCK:
            deferred = [(key, e.deferred) for key, e in _WRITTEN.items() if key.startswith(prefix) and e.deferred]
            for key, _ in deferred:
                _WRITTEN[key].deferred = None
        for key, step in deferred:
            _write_step(key, *step)


@contextmanager
def checkpointing(outs):
    """Around a ramp that checkpoints into the run directories `outs`: on leaving, however (the end, an
    error, an interrupt), the deferred checkpoints are written, so the last completed step is on disk."""
    try:
        yield
    finally:
        flush_steps(outs)


def start_part(out, realization, result=None):
    """Before a realization (re)starts: its CSV holds exactly the rows of `result` (a
    `load_part` result to continue) or none, dropping a row cut short by a kill, and the saved
    fields of steps after them (dropped by a cut-back) are removed."""
    path = _part(out, realization, ".csv")
    last = len(result.curve["step"]) - 1 if result is not None else -1
    with _LOCK:
        _WRITTEN[_key(out, realization)] = _Written(rows=last + 1)  # the rows this leaves on disk
    for f in Path(out, PARTIAL).glob(f"realization{realization}_step*.npz"):  # fields of dropped steps
        k = f.name[len(f"realization{realization}_step"):-4]
        if k.isdigit() and int(k) > last:
            with safe_files.writing(f):
                f.unlink(missing_ok=True)
    if result is None:  # a fresh start: no state (it may be one that could not be continued), no rows
        with safe_files.writing(path):
            _part(out, realization, ".state.npz").unlink(missing_ok=True)
            path.unlink(missing_ok=True)
        return
    buf = io.StringIO()
    buf.write(",".join(CURVE_COLUMNS) + "\n")
    for k in range(len(result.curve["step"])):
        buf.write(",".join(_fmt(result.curve[c][k]) for c in CURVE_COLUMNS) + "\n")
    _atomic_write(path, buf.getvalue())


def save_realization(out, result):
    """Mark a finished realization done; one that was not checkpointed step by step (a run
    without the checkpoint hook) is first put on disk at once."""
    from gfmd_contact.core.loading import RampState

    flush_steps([out])
    rows = len(result.curve["step"])
    if not _part(out, result.realization, ".csv").is_file():
        start_part(out, result.realization, result)
        for k in result.fields:
            _save_fields(out, result, k)
    last = int(result.curve["step"][-1]) if rows else -1
    _save_state(out, result, RampState(step=last, current=None, previous=None), done=True)
    with _LOCK:  # done: nothing of it is deferred any more (a long-lived worker runs many)
        _WRITTEN.pop(_key(out, result.realization), None)


def consistent_rows(path, last_step):
    """The longest prefix of a partial CSV that a checkpoint can trust: complete rows (newline-ended,
    every column a number) numbered 0, 1, 2, … up to `last_step`; (rows as dicts, rows in the file)."""
    try:
        lines = Path(path).read_text().split("\n")
    except FileNotFoundError:
        return [], 0
    total = sum(1 for line in lines[1:] if line)
    if lines[0] != ",".join(CURVE_COLUMNS):
        return [], total
    rows = []
    for i, line in enumerate(lines[1:-1]):  # the text after the last newline is a row cut short
        values = line.split(",")
        if i > last_step or len(values) != len(CURVE_COLUMNS):
            break
        try:
            row = {c: (int(float(v)) if c in ("step", "iterations", "converged") else float(v))
                   for c, v in zip(CURVE_COLUMNS, values)}
        except ValueError:
            break
        if row["step"] != i:
            break
        rows.append(row)
    return rows, total


def load_part(out, scene, realization, notes=None):
    """(result, state, done) of a realization found in out/partial, or None if it has no usable state.

    result holds the steps up to state.step (lists, ready to be continued), its saved
    fields, messages, reasons and notes; state is the `gfmd_contact.core.loading.RampState` to
    resume from (its arrays None when done). Damage is repaired, not refused: rows after
    the saved step (a kill between a row and its state, a second writer) are dropped; a CSV
    whose consistent prefix (`consistent_rows`) ends at a step m before the saved step is cut
    back to the last step j ≤ m whose saved fields carry the ramp's warm start (`_save_fields`:
    current, previous, slip_warned and the message counts after step j, exactly as the ramp had
    them, so the continuation equals an uninterrupted run's), messages and reasons of later steps
    dropped, not done; with no such j, or an unreadable state, None (the realization restarts).
    Each repair appends one line to `notes` (a list) if given.
    """
    from gfmd_contact.core.loading import RampState

    path = _part(out, realization, ".state.npz")
    if not path.is_file():
        return None
    csv_path = _part(out, realization, ".csv")
    try:
        with np.load(path) as z:
            step, done, slip = int(z["step"]), bool(z["done"]), bool(z["slip_warned"])
            text = json.loads(str(z["text"]))
            current = z["current"] if "current" in z else None
            previous = z["previous"] if "previous" in z else None
    except (OSError, ValueError, KeyError, EOFError) as exc:
        if notes is not None:
            notes.append(f"{path}: unreadable ({exc}): realization {realization} restarts from step 0")
        return None
    rows, total = consistent_rows(csv_path, step)
    if len(rows) < step + 1:
        where = (f"{csv_path}: {total} rows for {step + 1} saved steps, consistent only up to step {len(rows) - 1} "
                 "(rows missing, cut or out of order: written by another process?)")
        earlier = _saved_warm_start(out, realization, len(rows) - 1)
        if earlier is None:
            if notes is not None:
                notes.append(f"{where}; no warm start of a step up to {len(rows) - 1} is on disk (one is kept with "
                             f"the fields of each saved step, output.field_steps): realization {realization} "
                             f"restarts from step 0 ({step + 1} saved steps dropped)")
            return None
        if notes is not None:
            notes.append(f"{where}; kept steps 0–{earlier[0]} (the last of them whose warm start is on disk, with "
                         f"its saved fields), dropped {step - earlier[0]} saved step(s): realization {realization} "
                         f"continues from step {earlier[0] + 1}")
        step, current, previous, slip, (n_messages, n_reasons, n_notes) = earlier
        done, rows = False, rows[:step + 1]
        text.update(messages=text["messages"][:n_messages], reasons=text["reasons"][:n_reasons],
                    notes=text["notes"][:n_notes])
    elif total > len(rows) and notes is not None:
        notes.append(f"{csv_path}: {total} rows for {step + 1} saved steps: kept steps 0–{step}, dropped "
                     f"{total - len(rows)} row(s) written after the last saved step (a process killed between a row "
                     f"and its checkpoint, or a second writer); realization {realization} continues from step "
                     f"{step + 1}")
    h = surfaces.profile(scene.surface, realization)
    result = Result(scene=scene, method=text["method"], model=text["model"], realization=realization,
                    x=surfaces.grid(scene.surface.nodes, scene.surface.length), y=y_positions(scene.surface), h=h,
                    reasons=tuple(text["reasons"]), messages=text["messages"], notes=text["notes"])
    if text.get("fallback_steps"):
        result.diagnostics["fallback_steps"] = [k for k in text["fallback_steps"] if k <= step]
    if text.get("algorithms"):
        result.diagnostics["algorithms"] = text["algorithms"][:step + 1]
    if text.get("instabilities"):  # force control's events (gfmd_contact.core.force)
        result.diagnostics["instabilities"] = [e for e in text["instabilities"] if e["step"] <= step]
    for row in rows:
        result.append_step(**row)
    for k in range(step + 1):
        f = _part(out, realization, f"_step{k}.npz")
        if f.is_file():
            with np.load(f) as z:
                result.fields[k] = {name: z[name] for name in FIELD_NAMES}
                for name in z.files:
                    if name.startswith("diag_"):
                        result.diagnostics.setdefault(name[5:], {})[k] = z[name]
    return result, RampState(step=step, current=current, previous=previous, slip_warned=slip), done


def _saved_warm_start(out, realization, last):
    """(step, current, previous, slip_warned, (messages, reasons, notes) counts) of the highest step ≤ `last`
    whose saved fields carry the ramp's warm start (`_save_fields`), or None if none does."""
    found = []
    for f in Path(out, PARTIAL).glob(f"realization{realization}_step*.npz"):
        k = f.name[len(f"realization{realization}_step"):-4]
        if k.isdigit() and int(k) <= last:
            found.append((int(k), f))
    for k, f in sorted(found, reverse=True):
        try:
            with np.load(f) as z:
                if "ramp_current" in z:
                    return (k, z["ramp_current"], z["ramp_previous"], bool(z["ramp_slip_warned"]),
                            [int(c) for c in z["ramp_counts"]])
        except (OSError, ValueError, KeyError, EOFError):  # damaged: try an earlier one
            continue
    return None
