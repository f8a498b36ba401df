"""A live dashboard of the robot in the browser (thesis section 4.2, Fig. 4.9).

``ego run --dashboard``, ``ego serve --dashboard``, ``ego demo`` (on by default) and
``ego replay`` serve it: the e-puck from above with its sensors and LEDs, the path it
drove (and, on the emulator, the world and its true pose), the camera, the microphones,
the link's health and plots of any sensor; the page that holds control can drive, toggle
LEDs and sensors, and stop the robot. Modules: :mod:`~ego.servers.dashboard.control` (who may
act, and what they asked: sans-I/O), :mod:`~ego.servers.dashboard.access` (the token, the
login cookie, the Host names: sans-I/O), :mod:`~ego.servers.dashboard.pages` (the HTTP side:
login, files, security headers), :mod:`~ego.servers.dashboard.server` (aiohttp),
:mod:`~ego.servers.dashboard.live` (a robot's feed).
"""
