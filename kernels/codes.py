"""One table of the codes the 2D and 3D steppers share (issue 14): return codes of the
event loop, error codes (``ERR_*``, negative; ``rbimpact._setup.run_status`` names a
failed run's status after its code, e.g. ``ERR_PAINLEVE`` -> "painleve"), event kinds,
persistent-contact modes, policies and the feature switches of a compiled loop.
Every value is unique within its group, so a code means one thing in both dimensions.
"""

# return codes of run_loop
RC_DONE = 0
RC_MAX_EVENTS = 1
RC_BUFFER_FULL = 2

# errors (the run stops; the Python layer raises with the details of ``err``)
ERR_NO_SOLUTION = -1     # an impact has no solution in its law
ERR_NONFINITE = -2       # a state became non-finite
ERR_MISSED = -3          # a body is inside a plane or another body beyond gap_tol
ERR_TOI = -4             # a time-of-impact search did not converge
ERR_CHATTER = -5         # impacts accumulate at one point where no held mode exists
ERR_SEQ = -6             # sequential policy: contacts still approach after seq_max_steps
ERR_PGS = -7             # simultaneous policy: the joint solve did not converge
ERR_TIPPING = -8         # a face cannot hold the body and no pivot applies
ERR_STALL = -10          # too many events at one instant
ERR_TOO_MANY = -11       # more contacts at one instant than the workspace holds
ERR_JOINT_E = -12        # the joint solve with restitution e > 0 (not built)
ERR_ROT = -13            # 3D: the free rotation's integrator failed
ERR_UNSUPPORTED = -14    # a contact configuration the stepper does not handle (named)
ERR_PAINLEVE = -15       # held contact with no consistent force (Painleve)
ERR_CONTACT_STEPS = -16  # the integrator of a held contact exceeded its step limit
ERR_TWO_PLANES = -17     # 2D: accumulating on one plane while held by another (moving)
ERR_NOT_COMPILED = -18   # a handler the loop was compiled without (a bug of the switches)
ERR_FAR_ACCUMULATION = -19  # bounces accumulate only after max_accumulation_impacts
ERR_PERSISTENT_PAIR = -20   # two bodies stay in contact (persistent body-body contact,
                            # issue 16 item 2, not built); err[5] holds a PP_* reason
ERR_IDLE = -21           # idle_passes consecutive passes of the loop recorded no event
                         # (integrated or bounded motion that never reaches an event)

# Body pairs (issue 16). ``pr_off[q]`` of pair q: PR_ON searched for impacts; PR_OFF
# disabled for good (a perforating impact); PR_HIT had an impact at the instant just
# resolved (its next search checks whether the bodies stay in contact,
# ``decisions.pair_persistence``).
PR_ON = 0
PR_OFF = 1
PR_HIT = 2
PR_CHECK = 3         # 3D: ``pr_t[q]`` is not an impact but the time to search the pair
                     # again (a body of it held by an integrated contact: a distance bound)
PR_REL = 4           # 2D: its persistent contact just ended (a cluster contact lifted at
                     # g = g' = g'' = 0): its next search starts past that tangency
PR_WAIT = 5          # 2D: waits for the cluster entered at this instant (its bodies stay in
                     # contact, or are both held by pivot contacts), searched again right
                     # after the entry as a pair just hit (members: inside the cluster)
# Reasons of ERR_PERSISTENT_PAIR (err[5], a float): the run stops, naming the pair, when
PP_CHATTER = 1.0     # the impacts of a pair accumulate at one contact (re-contact within
                     # a rise of rest_length; round bodies: v_N^2 < 2 |g''| rest_length)
PP_TOGETHER = 2.0    # after a plastic impact the bodies ride together (no separation found)
PP_HELD = 3.0        # a body of the pair is held on a plane by an integrated contact
                     # (PM_PIVOT), or is in a moving cluster (PM_CLUSTER) while the other
                     # body is not (no closed-form motion to search)
# Reasons of a refused persistent 2D body-body contact (PM_CLUSTER, kernels/cluster2d.py):
PP_NO_MODE = 4.0     # cluster_select_modes: no consistent stick/slip/lift-off (Painleve)
PP_CLUSTER = 5.0     # cluster2d failed (err[6]: its CS_* status: singular, Painleve, steps,
                     # too many contacts) or the cluster holds more than the tables
PP_SHAPES = 6.0      # a cluster with an ellipse (2D) or a body other than a sphere (3D)
PP_FEATURE = 7.0     # 2D: a contact point leaves its feature and no switch is found (three
                     # gatherings of the cluster within CL_CHAT_RTOL sqrt(L / |g|))
PP_TWO = 8.0         # a second cluster while one is in motion, or a cluster body held
                     # otherwise (pivot, wedge)
PP_SPLIT = 9.0       # 3D: a body leaves a cluster that keeps body-body contacts (not built;
                     # 2D: it flies, stepper2d._cl_leave)
PP_STICK_SLIP = 10.0  # stick-slip events of a cluster accumulate (CL_CHAT_MAX of them
                      # closer than CL_CHAT_RTOL sqrt(L / |g|) apart: stepper2d)
PP_CORNER = 11.0     # 2D: two touching features the cluster's rows cannot describe (two
                     # sharp corners; err[6]: cluster2d_rows.PR_*)
PP_UNWATCHED = 12.0  # 2D: two bodies of a cluster that did not touch at its entry overlap
                     # after a pass (pairs without a contact row are checked, not watched)
PP_REENTRY = 13.0    # 2D: a pair's cluster ends and is entered again CL_CHAT_MAX times, each
                     # within CL_CHAT_RTOL sqrt(L / |g|) of the one before (no lasting mode)

# event kinds (ev_i[:, 0]); a persistent mode m (PM_SLIDE..PM_REST) is logged as kind m + 1
EV_IMPACT = 0
EV_CONTACT = 1
EV_SLIDE = 2
EV_ROLL = 3
EV_REST = 4
EV_RELEASE = 5
EV_CAPTURE = 6           # 3D: a face captured by the joint solve (capture option)
EV_PIVOT = 7
EV_STICK = 8
EV_IWC = 9               # "painleve": an impact without collision (a sliding contact at
                         # v_N = 0 with no consistent force takes an impulse)
EVENT_KINDS = ("impact", "contact", "slide", "roll", "rest", "release", "capture", "pivot",
               "stick", "painleve")

# persistent-contact modes (pm[:, 0])
PM_FLIGHT = 0
PM_SLIDE = 1
PM_ROLL = 2
PM_REST = 3
PM_PIVOT = 4             # integrated vertex, edge or boundary contact (pivot2d, pivot3d)
PM_WEDGED = 5            # held by two planes: 2D at rest on two contacts (wedge2d); 3D a
                         # sphere rolling (sliding if mu = 0) along their groove, or at rest
PM_CLUSTER = 6           # 2D: in persistent contact with other bodies (and planes), integrated
                         # by kernels/cluster2d.py (or frozen at rest)

# what a Painleve-inconsistent sliding contact does (the ``painleve`` option)
PAINLEVE_ERROR = 0       # the run stops with status "painleve", the contact named
PAINLEVE_IMPACT = 1      # an impact without collision (Darboux-Keller from v_N = 0)
PAINLEVE_OPTIONS = ("error", "impact")

# simultaneous-contact policies
POL_SIMULTANEOUS = 0
POL_SEQUENTIAL = 1

# Feature switches of a compiled loop: the loop takes one argument per feature, True, or
# None when the scene cannot reach it (``scene_features`` of each stepper). Numba prunes
# the ``is None`` branches by type before typing, so a scene compiles only the handlers
# it can reach, each pattern a cached specialization. A handler reached while switched off
# returns ERR_NOT_COMPILED with the feature's index in ``err``.
FEATURE_PIVOT = 0        # a polygon, rod, ellipse, box or capsule: held vertex/edge/face
FEATURE_WEDGE = 1        # 2D: two or more planes (rest on two contacts)
FEATURE_PAIR = 2         # round body pairs
FEATURE_JOINT = 3        # several contacts at one instant (the joint solve)
FEATURES = ("pivot", "wedge", "pair", "joint")
