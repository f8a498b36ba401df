"""The network protocol of ``ego serve``, spoken by both ends: frames, messages, the
handshake and the secret. Sans-I/O: bytes in, values out."""
