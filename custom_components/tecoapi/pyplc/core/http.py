"""Reading an HTTP answer without letting a device grow memory without bound."""

from __future__ import annotations

from typing import TYPE_CHECKING, Final

from .exceptions import ResponseTooLargeError

if TYPE_CHECKING:
    import aiohttp

READ_CHUNK: Final = 64 * 1024
"""Bytes taken from the connection at a time."""


async def read_limited(
    response: aiohttp.ClientResponse,
    limit: int,
    *,
    sender: str = "a device",
    chunk_size: int = READ_CHUNK,
) -> bytes:
    """Read a response's body, failing as soon as it passes ``limit`` bytes.

    An answer that declares more fails before a byte is read; one without a
    length (or lying about it) fails once it has passed the limit. Never more
    than ``limit + 1`` bytes are taken from the connection. ``sender`` names
    what would never send that much, for the message (``"a PLC"``).
    """
    declared = response.content_length
    if declared is not None and declared > limit:
        raise ResponseTooLargeError(
            f"The answer declares {declared} bytes, more than {sender} ever sends "
            f"({limit})",
            status=response.status,
            limit=limit,
        )
    chunks: list[bytes] = []
    received = 0
    while chunk := await response.content.read(min(chunk_size, limit + 1 - received)):
        received += len(chunk)
        if received > limit:
            raise ResponseTooLargeError(
                f"The answer passed {limit} bytes, more than {sender} ever sends",
                status=response.status,
                limit=limit,
                received=received,
            )
        chunks.append(chunk)
    return b"".join(chunks)
