"""HTTP for every source: failures as the core's errors, answers read within a cap."""

from __future__ import annotations

from contextlib import contextmanager
from typing import TYPE_CHECKING, Final

import aiohttp

from .exceptions import PlcConnectionError, PlcTlsError, ResponseTooLargeError

if TYPE_CHECKING:
    from collections.abc import Iterator

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


@contextmanager
def transport_errors(base_url: str) -> Iterator[None]:
    """Raise aiohttp's failures of a request to ``base_url`` as the core's.

    An untrusted certificate is :class:`PlcTlsError` (the user can act on it);
    any other failure to talk, a timeout included, :class:`PlcConnectionError`.
    """
    try:
        yield
    except aiohttp.ClientConnectorCertificateError as err:
        raise PlcTlsError(f"The TLS certificate of {base_url} is not trusted") from err
    except (aiohttp.ClientError, TimeoutError) as err:
        raise PlcConnectionError(
            f"Cannot talk to {base_url}: {type(err).__name__}"
        ) from err
