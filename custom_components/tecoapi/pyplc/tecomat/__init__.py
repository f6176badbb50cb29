"""Tecomat PLCs (Foxtrot, TC700): TecoApi over HTTP and PLCComS over TCP.

``TecoApiSession`` (the schedule: what to read on which poll) over
``TecoApiClient`` (HTTP, Digest, the services, discovery and the read planner);
``PlcComsSource`` (PLCComS alone) and ``PushedTecoApiSession`` (TecoApi, its values
pushed by PLCComS) over ``PlcComsClient``.
"""

from .plccoms.client import PlcComsClient
from .plccoms.pushed_session import PushedTecoApiSession
from .plccoms.source import PlcComsSource
from .tecoapi.client import TecoApiClient
from .tecoapi.planner import plan_reads
from .tecoapi.plans import PlannedRequest, ReadPlan
from .tecoapi.source import TecoApiSession

__all__ = [
    "PlannedRequest",
    "PlcComsClient",
    "PlcComsSource",
    "PushedTecoApiSession",
    "ReadPlan",
    "TecoApiClient",
    "TecoApiSession",
    "plan_reads",
]
