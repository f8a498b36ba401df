"""Worlds written the way Webots writes them, for the frame tests: an arena standing off
the origin and turned (R2023b, with its EXTERNPROTO lines), and an older world declared
NUE (R2021b, y up: no EXTERNPROTO lines then), each with a GPS and a Compass in one of
the E-puck's slots."""

from __future__ import annotations

_PROTOS = "https://raw.githubusercontent.com/cyberbotics/webots/R2023b/projects"

#: The arena's centre at (2, 1), turned a quarter turn: its 1 m side runs along world y.
OFF_ORIGIN = f"""#VRML_SIM R2023b utf8

EXTERNPROTO "{_PROTOS}/objects/backgrounds/protos/TexturedBackground.proto"
EXTERNPROTO "{_PROTOS}/objects/floors/protos/RectangleArena.proto"
EXTERNPROTO "{_PROTOS}/objects/factory/containers/protos/WoodenBox.proto"
EXTERNPROTO "{_PROTOS}/robots/gctronic/e-puck/protos/E-puck.proto"

WorldInfo {{
  basicTimeStep 32
}}
Viewpoint {{
  orientation -0.5 0.5 0.7 2
  position 2 1 3
}}
TexturedBackground {{
}}
RectangleArena {{
  translation 2 1 0
  rotation 0 0 1 1.5707963
  floorSize 1 0.5
}}
DEF CRATE WoodenBox {{
  translation 2.1 1.3 0.05
  rotation 0 0 1 1.5707963
  size 0.1 0.1 0.1
}}
DEF EPUCK E-puck {{
  translation 1.9 0.9 0
  rotation 0 0 1 3.1415926
  controller "supervised"
  supervisor TRUE
  turretSlot [
    GPS {{
    }}
    Compass {{
    }}
  ]
}}
"""

#: Webots before R2022a: x north, y up, z east; the arena's 1 m side along x (north).
NUE_WORLD = """#VRML_SIM R2021b utf8
WorldInfo {
  coordinateSystem "NUE"
  basicTimeStep 32
}
Viewpoint {
  orientation -1 0 0 1.2
  position 0 2 1
}
TexturedBackground {
}
RectangleArena {
  floorSize 1 0.6
}
DEF BOX Solid {
  translation 0.2 0.025 -0.1
  rotation 0 1 0 0.5
  children [
    Shape {
      geometry Box {
        size 0.1 0.05 0.04
      }
    }
  ]
  boundingObject Box {
    size 0.1 0.05 0.04
  }
}
DEF EPUCK E-puck {
  translation -0.1 0 0.2
  rotation 0 1 0 1
  controller "supervised"
  supervisor TRUE
  groundSensorsSlot [
    GPS {
    }
    Compass {
    }
  ]
}
"""
