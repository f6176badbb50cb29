"""Requests and wall time per poll: our client against the peer baseline, same PLC.

Both clients poll every point discovery found. Ours executes its read plan (values
only, and once with attributes); the peer reads each point with its own GetObject,
challenged by Digest first. Requests are counted on the PLC's side, on the wire.
"""

from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from functools import partial
import statistics
import time
from typing import Any

import aiohttp

from custom_components.tecoapi.pyplc.tecomat import ReadPlan, TecoApiClient

from .peer import PeerClient
from .plc_thread import PlcThread


@dataclass(frozen=True, slots=True, kw_only=True)
class PollingFigures:
    """Client-level figures for one program."""

    points: int
    api_objects: int
    skipped_roots: tuple[str, ...]
    planned_requests: int
    lower_bound: int
    requests_per_poll: float
    planned_requests_with_attrs: int
    lower_bound_with_attrs: int
    requests_per_poll_with_attrs: float
    poll_ms: float
    poll_with_attrs_ms: float
    missing_points: int
    challenges_after_first: int
    round_trips_per_request: float
    """Requests on the wire after the session's first challenge, per answered one."""
    peer_requests_per_poll: float
    peer_poll_ms: float
    polls: int
    peer_polls: int

    @property
    def request_ratio(self) -> float:
        """How many times fewer requests ours needs than the peer."""
        return self.peer_requests_per_poll / self.requests_per_poll

    @property
    def time_ratio(self) -> float:
        """How many times less wall time a poll of ours takes than the peer's."""
        return self.peer_poll_ms / self.poll_ms


@dataclass(frozen=True, slots=True)
class _Sample:
    requests: int
    seconds: float


async def _timed(plc: PlcThread, poll: Callable[[], Awaitable[Any]]) -> _Sample:
    """Run one poll; count the requests the PLC received and the wall time."""
    before = len(plc.requests)
    started = time.perf_counter()
    await poll()
    return _Sample(len(plc.requests) - before, time.perf_counter() - started)


def _per_poll(samples: list[_Sample]) -> tuple[float, float]:
    """Mean requests per poll and median milliseconds per poll."""
    return (
        statistics.fmean(sample.requests for sample in samples),
        statistics.median(sample.seconds for sample in samples) * 1000,
    )


async def measure_polling(
    plc: PlcThread, username: str, password: str, *, polls: int, peer_polls: int
) -> PollingFigures:
    """Discover with our client, then poll `polls` times each way and the peer too."""
    async with aiohttp.ClientSession() as session:
        client = TecoApiClient(session, plc.url, username, password)
        first = len(plc.requests)
        await client.get_info()
        catalogue = await client.discover()
        points = dict(catalogue.points)
        plans: dict[bool, ReadPlan] = {
            with_attrs: client.plan(points.values(), with_attrs=with_attrs)
            for with_attrs in (False, True)
        }
        missing: set[str] = set()

        async def poll(with_attrs: bool) -> None:
            result = await client.read(plans[with_attrs], points)
            missing.update(result.missing)

        samples: dict[bool, list[_Sample]] = {False: [], True: []}
        for with_attrs, series in samples.items():
            for _ in range(polls):
                series.append(await _timed(plc, partial(poll, with_attrs)))
        ours = plc.requests[first:]
        challenges = sum(1 for record in ours if record.status == 401)

        peer = PeerClient(session, plc.url, username, password)
        names = [point.path for point in points.values()]
        peer_samples = [
            await _timed(plc, lambda: peer.poll(names)) for _ in range(peer_polls)
        ]

    requests, poll_ms = _per_poll(samples[False])
    requests_attrs, poll_attrs_ms = _per_poll(samples[True])
    peer_requests, peer_ms = _per_poll(peer_samples)
    return PollingFigures(
        points=len(points),
        api_objects=sum(point.described for point in points.values()),
        skipped_roots=catalogue.skipped_groups,
        planned_requests=len(plans[False].requests),
        lower_bound=plans[False].lower_bound,
        requests_per_poll=requests,
        planned_requests_with_attrs=len(plans[True].requests),
        lower_bound_with_attrs=plans[True].lower_bound,
        requests_per_poll_with_attrs=requests_attrs,
        poll_ms=poll_ms,
        poll_with_attrs_ms=poll_attrs_ms,
        missing_points=len(missing),
        challenges_after_first=max(0, challenges - 1),
        round_trips_per_request=(len(ours) - 1) / max(1, len(ours) - challenges),
        peer_requests_per_poll=peer_requests,
        peer_poll_ms=peer_ms,
        polls=polls,
        peer_polls=peer_polls,
    )
