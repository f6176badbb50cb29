"""The peer baseline: what the existing public TecoApi integration does on every poll.

That integration reads each configured object with its own `GetObject?<name>`, one
after the other (a semaphore of one), and its HTTP authentication is not kept between
requests, so against a PLC that asks for Digest every request first meets the 401
challenge and then repeats with credentials: two round trips per object. This client
does exactly that, over the same aiohttp stack, so its figures are measured in the same
run as ours rather than estimated.
"""

from collections.abc import Iterable
from typing import Any
from urllib.parse import quote

import aiohttp
from yarl import URL

GET_OBJECT = "/TecoApi/GetObject?"
# Names as that integration sends them: dots and array brackets unescaped.
_SAFE = "._[]"


class PeerClient:
    """One GetObject per object, sequentially, each challenged by Digest first."""

    def __init__(
        self,
        session: aiohttp.ClientSession,
        base_url: str,
        username: str,
        password: str,
        *,
        timeout: float = 10.0,
    ) -> None:
        """Talk to the PLC at `base_url` (`http://host:port`) with these credentials."""
        self._session = session
        self._base_url = base_url.rstrip("/")
        self._username = username
        self._password = password
        self._timeout = aiohttp.ClientTimeout(total=timeout)

    async def get_object(self, name: str) -> Any:
        """Read one object (a whole T_ApiObject: value and attributes)."""
        # A fresh middleware holds no nonce: the PLC challenges this request first.
        digest = aiohttp.DigestAuthMiddleware(self._username, self._password)
        url = URL(self._base_url + GET_OBJECT + quote(name, safe=_SAFE), encoded=True)
        async with self._session.get(
            url, middlewares=(digest,), timeout=self._timeout
        ) as response:
            response.raise_for_status()
            return await response.json(content_type=None)

    async def poll(self, names: Iterable[str]) -> dict[str, Any]:
        """Read every object in turn; the JSON each answered, by name."""
        return {name: await self.get_object(name) for name in names}
