"""A study task's load steps reach the progress bar in batches (`gfmd_contact.app.study_task.REPORT_SECONDS`): one Dask
event per REPORT_SECONDS of solving and one at a ramp's last step (or at the task's end), each carrying its count, so
the bar's total is every step while a worker sends a few events per task instead of one per step (each cost the
solver ≈ 3 ms: the module's measured figures). A fake worker and clock stand in for Dask's."""

import pytest

from gfmd_contact.app import study_task


class FakeWorker:
    def __init__(self):
        self.events = []

    def log_event(self, topic, msg):
        self.events.append((topic, msg))


@pytest.fixture
def worker(monkeypatch):
    import distributed

    fake = FakeWorker()
    monkeypatch.setattr(distributed, "get_worker", lambda: fake)
    monkeypatch.setattr(study_task, "_reported", {"steps": 0, "since": None})
    return fake


def run_ramp(monkeypatch, steps, seconds_per_step, last=None):
    clock = [100.0]
    monkeypatch.setattr(study_task.time, "monotonic", lambda: clock[0])
    for k in range(steps + 1 if last is None else last + 1):
        clock[0] += seconds_per_step
        study_task._report_step(k, steps)


def test_fast_steps_are_sent_at_the_ramps_end(worker, monkeypatch):
    run_ramp(monkeypatch, 200, 1e-3)  # 201 steps in 0.2 s
    assert worker.events == [(study_task.STEP_TOPIC, 201)]


def test_slow_ramps_send_an_event_per_report_interval(worker, monkeypatch):
    per_step = 0.3 * study_task.REPORT_SECONDS
    run_ramp(monkeypatch, 200, per_step)
    counts = [msg for topic, msg in worker.events]
    assert sum(counts) == 201 and all(topic == study_task.STEP_TOPIC for topic, _ in worker.events)
    # a batch is sent at its first step REPORT_SECONDS after the batch's first: 5 steps (4 × 0.3 s ≥ 1 s)
    assert counts[:-1] == [5] * (201 // 5) and counts[-1] == 201 % 5


def test_a_ramp_that_stops_early_is_flushed_by_its_task(worker, monkeypatch):
    run_ramp(monkeypatch, 200, 1e-3, last=57)  # stopped at step 57 of 200 (a_rel reached, a failure)
    assert worker.events == []
    study_task.flush_steps()  # run_task and run_shared do this whatever ends them
    assert worker.events == [(study_task.STEP_TOPIC, 58)]
    study_task.flush_steps()
    assert len(worker.events) == 1  # nothing counted since: no event


def test_off_a_worker_nothing_is_sent(monkeypatch):
    import distributed

    def no_worker():
        raise ValueError("No worker found")

    monkeypatch.setattr(distributed, "get_worker", no_worker)
    monkeypatch.setattr(study_task, "_reported", {"steps": 0, "since": None})
    run_ramp(monkeypatch, 3, 1e-3)  # no error
    assert study_task._reported["steps"] == 0
