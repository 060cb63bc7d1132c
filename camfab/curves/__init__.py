"""The curve maths shared below the design file: exact curve values and plane helpers
(``plane``), lines-and-arcs profiles (``profile``), tolerance-driven sampling (``sampling``), the
follower's geometry (``follower``), and the outline of a cam drawn from its shape with the motion
it gives (``shaped``, ``contact``). Lengths are millimetres, angles radians."""
