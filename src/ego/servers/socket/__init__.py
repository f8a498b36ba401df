"""``ego serve`` over TCP, UDP and Unix sockets: the asyncio adapter of the session."""
