"""Column names of the scene tables the 2D and 3D steppers share (issue 14: named state).

``bint`` (int64, one row per body) and the first column of ``bflt`` (float64, one row per
body) mean the same in both dimensions; the other ``bflt`` columns are named in each
stepper (``stepper2d``: inertia, radius, ellipse axes; ``stepper3d``: principal moments,
radius, half extents). State rows are named in ``flight2d`` (``X, Y, ANGLE, ...``) and
``flight3d`` (offsets ``SX, SQ, SV, SW, SA, SAL``).
"""

# bint columns
B_KIND = 0      # shape kind (SH_* of each stepper)
B_FIRST = 1     # first row of the body's contact features (verts / feats)
B_COUNT = 2     # number of contact features
B_ROT = 3       # 3D: rotation kind (flight3d.ROT_*)
B_AXIS = 4      # 3D: symmetry axis (0, 1, 2) of an axisymmetric body

# bflt columns
B_MASS = 0      # mass (kg)

# pm columns: the persistent contact of a body
M_MODE = 0      # mode (codes.PM_*)
M_PLANE = 1     # the plane it is held on
M_FEAT = 2      # 2D: face vertex 0, or the held vertex (PM_PIVOT); 3D: the face
M_AUX = 3       # 2D: face vertex 1, or the held contact's status (0 stick, +-1 slide),
                # or REL_TANGENT in flight just after a tangential release; 3D: AUX_INTEGRATE
                # on a sphere whose slide curves (integrated from its ttr on)
M_PLANE2 = 4    # 2D: the second plane of a body held on two planes (PM_PIVOT), else -1
M_FEAT2 = 5     # 2D: the vertex held on M_PLANE2
N_PM = 6        # pm columns (3D uses the first four)

# cid header of a persistent body-body contact (a cluster; stepper2d with cluster2d,
# stepper3d with cluster3d): cid[CL_HDR:] holds the stepper index of each cluster row, then
# the stepper source of each contact row (a plane p >= 0, or -2 - q for pair q)
CL_N = 0         # members (0: no cluster)
CL_NK = 1        # active contacts
CL_NC = 2        # candidates
CL_EV = 3        # event pending at the leader's ttr (the cluster kernel's CE_*)
CL_IDX = 4       # its index
CL_LEAD = 5      # the leader (stepper body index), -1
CL_FROZEN = 6    # 1: at rest (frozen)
CL_PEND = 7      # pair whose impacts accumulate (enter a cluster at the next pass), -1
CL_CHAT = 8      # consecutive mode events closer than CL_CHAT_RTOL T (stick-slip chatter)
CL_SWITCH = 9    # 2D: 1 once the cluster was gathered again at a feature switch (its time:
                 # the spare slot of cw before the last)
CL_HDR = 10
CL_CHAT_RTOL = 1e-6
"""Mode events of a cluster closer than this times sqrt(L / |g|) are chatter (CL_CHAT)."""
CL_CHAT_MAX = 50
"""Consecutive chattering mode events after which the cluster is refused (PP_STICK_SLIP)."""
CL_REENTRY_HOLD = 2
"""2D: from this many consecutive entries of a cluster closer than CL_CHAT_RTOL T apart (a
contact that ends and starts again: an e = 0.3 contact, or a rod's landings on a face,
accumulating), every touching contact of the entering pair is held, none made a candidate
(the limit of the accumulation)."""
NCAND = 64       # candidate contact rows of a cluster (a stack of five boxes on a floor: 18;
#                  eight dominoes: each one's corners off the floor, 40 to 50)
