"""Affine estimate of the HCP lattice's shear peak under paper 000's pair law, nu = 0 (4 Dec probe).

Every bond follows the homogeneous pure shear eps_xy = gamma / 2 (simple shear with the spins turning
at the rotation rate, which is their torque-free state when k_T = k_N as at nu = 0), so each bond's
normal stretch and tangential slip are known in closed form; the normal force follows eqs 2-3
(linear to delta_e, linear softening to delta_f) and the tangential force eqs 4-5 (k_T delta_T capped
at F'_mT). The virial sum over the 12 neighbours gives sigma_xy(gamma); the script prints its peak over
sigma_T. No relaxation of the lattice is allowed, so it is an upper estimate of a test whose lattice
can slip. Also printed: the shear stress the tangential caps carry alone (every spring at F_mT, no
normal force), the share eq 11 is derived for; the rest of a peak is the normal forces of bonds
inclined to the shear (paper 000's footnote on the strengths: "both the tensile and the shear
strength will contribute to the actual strength of the assembly"). Table 4 material, nu = 0 (A_N = A_T = sqrt(2) r^2, k_N = k_T). Pure python, no imports
beyond math:  python3 docs/probes/hcp_affine_shear.py
"""
import math

E, SIGMA_N, SIGMA_T, D = 1.0, 0.2, 0.1, 1.0


def neighbours():
    """The 12 unit bond vectors of HCP with close-packed layers in the x-y plane, rows along x."""
    out = [(math.cos(math.radians(60 * a)), math.sin(math.radians(60 * a)), 0.0) for a in range(6)]
    p = 1 / math.sqrt(3)
    for zs in (1, -1):
        for a in (30, 150, 270):
            t = math.radians(a)
            out.append((p * math.cos(t), p * math.sin(t), zs * math.sqrt(2 / 3)))
    return out


def turned(dirs, layers_parallel_to_walls, row_angle):
    """Rows turned by row_angle in their plane; layers moved to the x-z plane if asked."""
    c, s = math.cos(math.radians(row_angle)), math.sin(math.radians(row_angle))
    rows = [(c * x - s * y, s * x + c * y, z) for (x, y, z) in dirs]
    return [(x, z, y) for (x, y, z) in rows] if layers_parallel_to_walls else rows


def peak(dirs, softening):
    """First peak of sigma_xy / sigma_T (a drop of 10 % ends it) and the engineering shear strain
    where it falls."""
    area = D * D / (2 * math.sqrt(2))
    k = area * E / D
    volume = D ** 3 / math.sqrt(2)
    d_e = D * SIGMA_N / E
    d_f = d_e * softening
    best = (0.0, 0.0)
    for i in range(1, 10000):
        eps = i * 1e-4
        sxy = 0.0
        for nx, ny, nz in dirs:
            u = (eps * D * ny, eps * D * nx, 0.0)
            dn = u[0] * nx + u[1] * ny
            ut = (u[0] - dn * nx, u[1] - dn * ny, -dn * nz)
            if dn <= d_e:
                fn = k * dn
            elif dn < d_f:
                fn = k * d_e * (d_f - dn) / (d_f - d_e)
            else:
                fn = 0.0
            cap = area * SIGMA_T * min(max((d_f - dn) / d_f, 0.0), 1.0)
            tl = math.sqrt(sum(q * q for q in ut))
            ft = min(k * tl, cap)
            fx = fn * nx + (ft * ut[0] / tl if tl > 0 else 0.0)
            fy = fn * ny + (ft * ut[1] / tl if tl > 0 else 0.0)
            sxy += 0.5 * D * 0.5 * (fx * ny + fy * nx)
        sxy /= volume
        if sxy > best[0]:
            best = (sxy, 2 * eps)
        elif sxy < 0.9 * best[0]:
            # The first peak: past it the compressed bonds, which never fail, would carry the
            # stress up again at strains where an affine lattice means nothing.
            break
    return best[0] / SIGMA_T, best[1]


def caps_only(dirs):
    """sigma_xy / sigma_T with every tangential spring at its cap F_mT = A_T sigma_T (eq 11) along its
    slip and no normal force: the share of the shear that eq 11 is derived for."""
    area = D * D / (2 * math.sqrt(2))
    volume = D ** 3 / math.sqrt(2)
    sxy = 0.0
    for nx, ny, nz in dirs:
        u = (ny, nx, 0.0)
        dn = u[0] * nx + u[1] * ny
        ut = (u[0] - dn * nx, u[1] - dn * ny, -dn * nz)
        tl = math.sqrt(sum(q * q for q in ut))
        if tl > 0:
            f = area * SIGMA_T
            sxy += 0.5 * D * 0.5 * (f * ut[0] / tl * ny + f * ut[1] / tl * nx)
    return sxy / volume / SIGMA_T


def shear_modulus(dirs):
    """G / E at small strain, uncapped: 1/2 at nu = 0 if the constants are those of eqs 7-8, 15-16."""
    area = D * D / (2 * math.sqrt(2))
    k, volume, eps = area * E / D, D ** 3 / math.sqrt(2), 1e-6
    sxy = sum(0.5 * D * 0.5 * (k * eps * D * ny * ny + k * eps * D * nx * nx) for nx, ny, _ in dirs)
    return sxy / volume / (2 * eps) / E


if __name__ == "__main__":
    base = neighbours()
    print(f"check: G / E at small strain {shear_modulus(base):.6f} (nu = 0: 0.5)")
    cases = [
        ("layers normal to the walls, rows along the shear (shipped)", False, 0),
        ("layers normal to the walls, rows turned 90 deg", False, 90),
        ("layers parallel to the walls, rows along the shear", True, 0),
        ("layers parallel to the walls, rows across the shear", True, 90),
    ]
    for label, parallel, angle in cases:
        dirs = turned(base, parallel, angle)
        p, g = peak(dirs, 1.0)
        print(f"{label}: tangential caps alone {caps_only(dirs):.3f} sigma_T; "
              f"affine first peak (d0 > d_c, s = 0) {p:.3f} sigma_T at gamma {g:.3f}")
