"""The one place that says where everything sits: the state vector, the scalar parameter vector
of the kernels, and the columns of the internal record.

State vector ``y`` of a bearing with ``Z`` elements, ``N = 5 + Z`` degrees of freedom
(positions first, then their velocities in the same order; SI: m, m/s):

====================  ===================================================================
index                 degree of freedom
====================  ===================================================================
``0, 1``              inner ring with the shaft, ``x_i, y_i`` (``x``: the load direction)
``2, 3``              outer ring with the housing, ``x_o, y_o``
``4``                 resonator (sensor structure), absolute displacement along the sensor axis
``5 ... 5 + Z - 1``   element ``j``: displacement along its contact normal, outwards
``N ... 2N - 1``      the velocities of the above
====================  ===================================================================
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["StateLayout", "P_NAMES", "P_SIZE", "REC_FIXED", "REC_SIZE_FIXED", "REC_CONTACT"]


@dataclass(frozen=True)
class StateLayout:
    """Index map of the state vector of a bearing with ``z`` elements (module docstring)."""

    z: int

    #: inner ring x, y; outer ring x, y; resonator
    XI = 0
    YI = 1
    XO = 2
    YO = 3
    RES = 4
    ELEM0 = 5

    @property
    def n_dof(self) -> int:
        """Degrees of freedom ``N = 5 + Z``."""
        return self.ELEM0 + self.z

    @property
    def size(self) -> int:
        """Length of the state vector ``2 N``."""
        return 2 * self.n_dof

    def element(self, j: int) -> int:
        """Index of element ``j``'s displacement (its velocity: ``+ n_dof``).

        Parameters
        ----------
        j : int
            Element number, ``0 <= j < Z``.

        Returns
        -------
        int
            Index into the state vector.

        Raises
        ------
        ValueError
            ``j`` outside ``0 .. z - 1``.
        """
        if not 0 <= j < self.z:
            raise ValueError(f"element: got {j!r}; allowed: 0 <= j < {self.z}")
        return self.ELEM0 + j

    def velocity(self, i: int) -> int:
        """Index of the velocity of degree of freedom ``i``.

        Parameters
        ----------
        i : int
            Index of a position.

        Returns
        -------
        int
            ``i + N``.
        """
        return i + self.n_dof


#: Scalar parameters of the kernels, in the order of the float vector ``P`` (SI). ``ms, ks, cs``
#: shaft with inner ring (mass, support stiffness, support damping); ``mh, kh, ch`` outer ring
#: with housing; ``mr, kr, cr`` resonator; ``sens_c, sens_s`` cosine and sine of the sensor
#: axis; ``me`` element mass; ``ki, ko`` load-deflection constants of the inner and outer
#: contact (``Q = K delta^n``); ``n``; ``cc`` contact damping (N s/m); ``gap`` a quarter of the
#: diametral clearance ``P_d / 4`` (each contact's share); ``ca`` cos(contact angle); ``fx, fy``
#: applied force on the shaft; ``fc`` centrifugal force along the normal; ``ri, ro`` raceway
#: contact radii (arc length per radian); ``drace`` 0 none / 1 outer / 2 inner / 3 element
#: defect; ``dang`` the defect's angle at ``t = 0``; ``ws`` shaft rate (rad/s); ``ct0, cdt``
#: first time and spacing of the cage-angle nodes; ``n15`` 1 when ``n == 3/2`` (sqrt instead of
#: pow). A pit on element 0 (``drace`` 3): ``re`` the element radius; ``spr`` the element's
#: spin relative to the cage per radian of cage (BSF / FTF); ``bi2, bo2`` the squared Hertz
#: axial semi-axis per metre of approach of the inner and outer contact (``b^2 = b_1^2 K^(2/3)
#: delta``, the pit strikes only within it); ``turn0`` the cage turn of the orientation
#: table's first row; ``nx2, nd2, nor`` the sizes of the inner contact law's nodes and of the
#: orientation rows packed in ``P`` after these scalars (``kernels.pit_arrays``).
P_NAMES = ("ms", "ks", "cs", "mh", "kh", "ch", "mr", "kr", "cr", "sens_c", "sens_s", "me", "ki",
           "ko", "n", "cc", "gap", "ca", "fx", "fy", "fc", "ri", "ro", "drace", "dang", "ws",
           "ct0", "cdt", "n15", "re", "spr", "bi2", "bo2", "turn0", "nx2", "nd2", "nor")
P_SIZE = len(P_NAMES)

#: Fixed columns of the internal record (then the ``Z`` element loads, then the ``Z`` element
#: velocities along their normals and :data:`REC_CONTACT`, point-sampled): the force the elements pass
#: to the outer ring (x, y), the outer ring/housing displacement and acceleration (x, y), the
#: resonator displacement and acceleration, the defect contact force, the inner ring (x, y).
REC_FIXED = ("housing_force_x", "housing_force_y", "housing_disp_x", "housing_disp_y",
             "housing_acc_x", "housing_acc_y", "resonator_disp", "resonator_acc",
             "defect_force", "inner_disp_x", "inner_disp_y")
REC_SIZE_FIXED = len(REC_FIXED)
#: The record's last column: which contact reads the defect law (+1 outer, -1 inner, 0 none).
REC_CONTACT = "defect_contact"
