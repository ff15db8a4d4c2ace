"""Derived constants (GENERATED FILE, do not edit).

Written by ``python -m derivations.codegen`` from the exact results in ``derivations/``;
``python -m derivations.codegen --check`` and the test suite fail when it is stale. The
same names and values as ``shaders/generated/constants.glsl``, in full double
precision. The comment above each constant gives its closed form and derivation.
"""

# 4*atan(sqrt(11)/33)  [solid_angles.front_face]
FRONT_FACE_SOLID_ANGLE = 0.4006696846462392
# -pi/3 + 2*atan(3*sqrt(11)/11)  [solid_angles.side_face]
SIDE_FACE_SOLID_ANGLE = 0.42343135443673907
# 2*pi/3  [solid_angles.cube_face]
CUBE_FACE_SOLID_ANGLE = 2.0943951023931957
# 4*pi  [solid_angles.sphere]
FOUR_PI = 12.566370614359172
# pi  [solid_angles.projected_hemisphere]
PI = 3.141592653589793
# 1/(2*sqrt(pi))  [sh.c0]
SH_C0 = 0.28209479177387814
# sqrt(3)/(2*sqrt(pi))  [sh.c1]
SH_C1 = 0.4886025119029199
# sqrt(pi)/2  [sh.coslobe_c0]
SH_COSLOBE_C0 = 0.886226925452758
# sqrt(3)*sqrt(pi)/3  [sh.coslobe_c1]
SH_COSLOBE_C1 = 1.0233267079464885
# 2*sqrt(3)*sqrt(pi)/3  [sh.net_flux_c1]
SH_NET_FLUX_C1 = 2.046653415892977
# 2*sqrt(pi)  [sh.flux_factor]
SH_FLUX_FACTOR = 3.544907701811032
# 1/(2*sqrt(pi))  [sh.l2_c0]
SH_L2_C0 = 0.28209479177387814
# sqrt(3)/(2*sqrt(pi))  [sh.l2_c1]
SH_L2_C1 = 0.4886025119029199
# sqrt(15)/(2*sqrt(pi))  [sh.l2_c2]
SH_L2_C2 = 1.0925484305920792
# sqrt(5)/(4*sqrt(pi))  [sh.l2_c3]
SH_L2_C3 = 0.31539156525252
# sqrt(15)/(4*sqrt(pi))  [sh.l2_c4]
SH_L2_C4 = 0.5462742152960396
# sqrt(pi)/2  [sh.l2_coslobe_c0]
SH_L2_COSLOBE_C0 = 0.886226925452758
# sqrt(3)*sqrt(pi)/3  [sh.l2_coslobe_c1]
SH_L2_COSLOBE_C1 = 1.0233267079464885
# sqrt(5)*sqrt(pi)/8  [sh.l2_coslobe_c2]
SH_L2_COSLOBE_C2 = 0.4954159122007514
# sqrt(15)*sqrt(pi)/8  [sh.l2_lobe_c2]
SH_L2_LOBE_C2 = 0.8580855308097834
# sqrt(5)*sqrt(pi)/16  [sh.l2_lobe_c3]
SH_L2_LOBE_C3 = 0.2477079561003757
# sqrt(15)*sqrt(pi)/16  [sh.l2_lobe_c4]
SH_L2_LOBE_C4 = 0.4290427654048917
# 1/pi  [corrections.injection_pi.flux_factor]
INV_PI = 0.3183098861837907
# sqrt(5)/5  [propagation.side_eval_small]
SIDE_EVAL_SMALL = 0.4472135954999579
# 2*sqrt(5)/5  [propagation.side_eval_big]
SIDE_EVAL_BIG = 0.8944271909999159
# 1/2  [propagation.front_share_dx11]
DX11_FRONT_SHARE = 0.5
# 1/3  [propagation.side_share_dx11]
DX11_SIDE_SHARE = 0.3333333333333333
# -2*atan(sqrt(11)/33) + 2*atan(sqrt(19)/19)  [neighbours26.edge_face]
EDGE_FACE_SOLID_ANGLE = 0.2506919694731428
# -2*atan(sqrt(19)/19) + atan(sqrt(11)/33) + pi/6  [neighbours26.corner_face]
CORNER_FACE_SOLID_ANGLE = 0.17273938496359623
# 3*sqrt(13)/13  [neighbours26.edge_eval_big]
EDGE_EVAL_BIG = 0.8320502943378437
# 2*sqrt(13)/13  [neighbours26.edge_eval_small]
EDGE_EVAL_SMALL = 0.5547001962252291
# 3*sqrt(17)/17  [neighbours26.corner_eval_big]
CORNER_EVAL_BIG = 0.7276068751089989
# 2*sqrt(17)/17  [neighbours26.corner_eval_small]
CORNER_EVAL_SMALL = 0.48507125007266594
# 1/(4*pi)  [media.isotropic_phase]
INV_FOUR_PI = 0.07957747154594767
# printed in the DirectX 11 LPV implementation article; exact 1/(2*sqrt(pi)) (rounded)
#   [errata.dx11.sh_c0]
PUBLISHED_SH_C0 = 0.282094792
# printed in the DirectX 11 LPV implementation article; exact sqrt(3)/(2*sqrt(pi)) (rounded)
#   [errata.dx11.sh_c1]
PUBLISHED_SH_C1 = 0.488602512
# printed in the DirectX 11 LPV implementation article; exact sqrt(pi)/2 (correct)
#   [errata.dx11.coslobe_c0]
PUBLISHED_SH_COSLOBE_C0 = 0.886226925
# printed in the DirectX 11 LPV implementation article; exact sqrt(3)*sqrt(pi)/3 (rounded)
#   [errata.dx11.coslobe_c1]
PUBLISHED_SH_COSLOBE_C1 = 1.02332671
# printed in the DirectX 11 LPV implementation article; exact pi (truncated)  [errata.dx11.pi]
PUBLISHED_PI = 3.1415926
# printed in the DirectX 11 LPV implementation article; exact 4*atan(sqrt(11)/33) (correct)
#   [errata.dx11.front_solid_angle]
PUBLISHED_FRONT_FACE_SOLID_ANGLE = 0.4006696846
# printed in the DirectX 11 LPV implementation article; exact -pi/3 + 2*atan(3*sqrt(11)/11) (wrong)
#   [errata.dx11.side_solid_angle]
PUBLISHED_SIDE_FACE_SOLID_ANGLE = 0.4234413544
# printed in the DirectX 11 LPV implementation article; exact sqrt(5)/5 (truncated)
#   [errata.dx11.side_eval_small]
PUBLISHED_SIDE_EVAL_SMALL = 0.4472135
# printed in the DirectX 11 LPV implementation article; exact 2*sqrt(5)/5 (correct)
#   [errata.dx11.side_eval_big]
PUBLISHED_SIDE_EVAL_BIG = 0.894427
# printed in the DirectX 11 LPV implementation article; exact none (not derivable)
#   [errata.dx11.surfel_weight]
PUBLISHED_SURFEL_WEIGHT = 0.015

# constant name -> the derivation it comes from (derivations.registry.get)
DERIVATION: dict[str, str] = {
    "FRONT_FACE_SOLID_ANGLE": "solid_angles.front_face",
    "SIDE_FACE_SOLID_ANGLE": "solid_angles.side_face",
    "CUBE_FACE_SOLID_ANGLE": "solid_angles.cube_face",
    "FOUR_PI": "solid_angles.sphere",
    "PI": "solid_angles.projected_hemisphere",
    "SH_C0": "sh.c0",
    "SH_C1": "sh.c1",
    "SH_COSLOBE_C0": "sh.coslobe_c0",
    "SH_COSLOBE_C1": "sh.coslobe_c1",
    "SH_NET_FLUX_C1": "sh.net_flux_c1",
    "SH_FLUX_FACTOR": "sh.flux_factor",
    "SH_L2_C0": "sh.l2_c0",
    "SH_L2_C1": "sh.l2_c1",
    "SH_L2_C2": "sh.l2_c2",
    "SH_L2_C3": "sh.l2_c3",
    "SH_L2_C4": "sh.l2_c4",
    "SH_L2_COSLOBE_C0": "sh.l2_coslobe_c0",
    "SH_L2_COSLOBE_C1": "sh.l2_coslobe_c1",
    "SH_L2_COSLOBE_C2": "sh.l2_coslobe_c2",
    "SH_L2_LOBE_C2": "sh.l2_lobe_c2",
    "SH_L2_LOBE_C3": "sh.l2_lobe_c3",
    "SH_L2_LOBE_C4": "sh.l2_lobe_c4",
    "INV_PI": "corrections.injection_pi.flux_factor",
    "SIDE_EVAL_SMALL": "propagation.side_eval_small",
    "SIDE_EVAL_BIG": "propagation.side_eval_big",
    "DX11_FRONT_SHARE": "propagation.front_share_dx11",
    "DX11_SIDE_SHARE": "propagation.side_share_dx11",
    "EDGE_FACE_SOLID_ANGLE": "neighbours26.edge_face",
    "CORNER_FACE_SOLID_ANGLE": "neighbours26.corner_face",
    "EDGE_EVAL_BIG": "neighbours26.edge_eval_big",
    "EDGE_EVAL_SMALL": "neighbours26.edge_eval_small",
    "CORNER_EVAL_BIG": "neighbours26.corner_eval_big",
    "CORNER_EVAL_SMALL": "neighbours26.corner_eval_small",
    "INV_FOUR_PI": "media.isotropic_phase",
    "PUBLISHED_SH_C0": "errata.dx11.sh_c0",
    "PUBLISHED_SH_C1": "errata.dx11.sh_c1",
    "PUBLISHED_SH_COSLOBE_C0": "errata.dx11.coslobe_c0",
    "PUBLISHED_SH_COSLOBE_C1": "errata.dx11.coslobe_c1",
    "PUBLISHED_PI": "errata.dx11.pi",
    "PUBLISHED_FRONT_FACE_SOLID_ANGLE": "errata.dx11.front_solid_angle",
    "PUBLISHED_SIDE_FACE_SOLID_ANGLE": "errata.dx11.side_solid_angle",
    "PUBLISHED_SIDE_EVAL_SMALL": "errata.dx11.side_eval_small",
    "PUBLISHED_SIDE_EVAL_BIG": "errata.dx11.side_eval_big",
    "PUBLISHED_SURFEL_WEIGHT": "errata.dx11.surfel_weight",
}
