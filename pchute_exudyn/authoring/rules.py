"""The assumed numbers that size every case ``pchute new`` writes (the single-system descent, ``authoring.descent``,
and the dual deploy, ``authoring.rocket``): canopy areal mass, line strain and damping, the confluence's mass, the
bridles' attach circle, the opening's overshoot decay and the canopy's coefficients at every angle. Each is written
into the file beside the number it sizes; docs/models/sources.md lists them as assumed."""

MER_DRAG_AREA = 178.47 * 0.46
"""The default canopy's drag area (m^2): MER's parachute, S0 178.47 m^2 at C_A 0.46 (cases/mer/base.toml)."""
CANOPY_AREAL_MASS = 0.15
"""Canopy mass per reference area (kg/m^2) when none is given: canopy cloth, suspension lines and hardware
(assumed; light nylon canopies run about 0.1 to 0.3 kg/m^2)."""
LINE_STRAIN = 0.025
"""Stretch (-) of each line under its share of the vehicle's weight in steady descent (MER's riser: 2.6 %)."""
LINE_DAMPING_TIME = 0.01
"""Line damping / stiffness (s): MER's 470 N s/m on 47 000 N/m."""
CONFLUENCE_MASS_FRACTION = 0.002
"""Confluence mass / vehicle mass (-) when none is given (assumed: links and swivel)."""
ATTACH_RADIUS = 0.35
"""Bridle attach circle / vehicle diameter (-)."""
OVERINFLATION_DECAY = 0.25
"""The overshoot's fall (``overinflation_decay``) as a fraction of the fill time at the release airspeed (assumed)."""
AXIAL_FLAT_TO_DEG = 60.0
"""C_A(alpha') is C_D0 up to this angle (deg), then falls linearly to 0 at 90 deg (assumed shape): a canopy
symmetric fore and aft has no axial force edge-on, so the force is continuous as the canopy turns past 90 deg (a
constant C_A changes sign there: a jump no implicit step can cross, and an attitude the canopy slides along;
docs/models/aerodatabase.md, "Edge-on"). Measured canopy tables fall with the angle too (cases/cev_pa1_aero.toml)."""
EDGE_ON_NORMAL = 0.25
"""C_N at 90 deg (-, on S0), assumed: an edge-on canopy's side-on projected area (half the disc of its projected
diameter 0.67 D0, about 0.22 S0) at a bluff body's drag coefficient near 1.1: the cross-flow drag that slows a canopy
thrown edge-on by an opening or a gust, so that its riser pulls it back (MER's table ends at 0)."""
NORMAL_COEFFICIENT = ([0.0, 5.0, 10.0, 15.0, 20.0, 30.0, 45.0, 60.0, 90.0],
                      [0.0, 0.040, 0.080, 0.110, 0.130, 0.150, 0.140, 0.110, EDGE_ON_NORMAL])
"""C_N(alpha'): MER's zero-trim parachute table (docs/models/mer.md: a stable canopy's restoring force) to 60 deg,
then rising to the cross-flow drag of a canopy seen edge-on, EDGE_ON_NORMAL at 90 deg (MER's table ends at 0)."""
