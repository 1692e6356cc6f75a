"""Shared mechanics: frames and rotations, inertia and shapes, rolling, tops, free bodies, Floquet
theory, gravity, continuation of periodic orbits.  Used by two or more exercises each."""
