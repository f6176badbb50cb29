"""Waiting, without sleeping, for what a client does by itself."""

import asyncio
from typing import Any

from custom_components.tecoapi.pyplc.tecomat import PlcComsClient
from custom_components.tecoapi.pyplc.tecomat.plccoms.events import ConnectionChanged


async def connected(client: PlcComsClient, wait: float) -> None:
    """Wait until a PLCComS client is connected (``wait`` seconds at most)."""
    if client.connected:
        return
    ready = asyncio.get_running_loop().create_future()

    def heard(event: Any) -> None:
        if (
            isinstance(event, ConnectionChanged)
            and event.connected
            and not ready.done()
        ):
            ready.set_result(None)

    unsubscribe = client.subscribe(heard)
    try:
        async with asyncio.timeout(wait):
            await ready
    finally:
        unsubscribe()
