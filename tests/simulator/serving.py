"""Serving a simulator's aiohttp application on a TCP port."""

import ssl

from aiohttp import web


async def serve(
    app: web.Application,
    host: str,
    port: int,
    ssl_context: ssl.SSLContext | None = None,
) -> tuple[web.AppRunner, int]:
    """Listen on host:port (0 picks a free port); return the runner and the port bound.

    HTTPS with an SSL context. A port that cannot be bound leaves nothing running;
    the runner's cleanup stops serving, giving open requests a second to end.
    """
    runner = web.AppRunner(
        app, access_log=None, handle_signals=False, shutdown_timeout=1.0
    )
    await runner.setup()
    try:
        await web.TCPSite(runner, host, port, ssl_context=ssl_context).start()
    except BaseException:
        await runner.cleanup()
        raise
    return runner, runner.addresses[0][1]


def dropped(request: web.Request) -> web.Response:
    """Close the TCP connection without a byte of answer (a lost answer)."""
    if request.transport is not None:
        request.transport.abort()
    return web.Response(status=500)
