"""Core layer: frames, kinematics, rigid-body, added-mass and Coriolis matrices, fluid
properties. numpy only; plain floats and arrays in SI units."""
