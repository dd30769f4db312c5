"""The UV sphere both asset scripts (make_layered_balls.py, make_surface_balls.py) build on: radius
1 at the origin, 64 x 32 segments, counter-clockwise seen from outside, no triangle of zero area at
the poles. Each vertex's tangent runs along its line of latitude."""
import math

SEGMENTS, RINGS = 64, 32


def sphere():
    """(positions, tangents, indices): the positions are also the normals."""
    positions, tangents, indices = [], [], []
    for ring in range(RINGS + 1):
        theta = math.pi * ring / RINGS
        for segment in range(SEGMENTS + 1):
            phi = 2.0 * math.pi * segment / SEGMENTS
            positions.append((math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi)))
            tangents.append((-math.sin(phi), 0.0, math.cos(phi), 1.0))
    for ring in range(RINGS):
        for segment in range(SEGMENTS):
            a = ring * (SEGMENTS + 1) + segment
            b = a + SEGMENTS + 1
            if ring > 0:
                indices += [a, a + 1, b]
            if ring < RINGS - 1:
                indices += [a + 1, b + 1, b]
    return positions, tangents, indices
