"""ego's benchmarks: the thesis' tables reproduced on this library, with peers side by side."""
