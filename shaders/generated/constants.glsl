#version 430 core
// GENERATED FILE, do not edit. Written by `python -m derivations.codegen` from the exact
// results in derivations/ (see derivations/registry.py); `python -m derivations.codegen --check`
// and the test suite fail when it is stale. Shaders pull it in with an include
// directive naming generated/constants.glsl (the program loader resolves it).
// Each line: value to 12 significant digits  // closed form  [derivation]

#ifndef LPV_GENERATED_CONSTANTS
#define LPV_GENERATED_CONSTANTS

const float FRONT_FACE_SOLID_ANGLE = 0.400669684646;  // 4*atan(sqrt(11)/33)  [solid_angles.front_face]
const float SIDE_FACE_SOLID_ANGLE = 0.423431354437;  // -pi/3 + 2*atan(3*sqrt(11)/11)  [solid_angles.side_face]
const float CUBE_FACE_SOLID_ANGLE = 2.09439510239;  // 2*pi/3  [solid_angles.cube_face]
const float FOUR_PI = 12.5663706144;  // 4*pi  [solid_angles.sphere]
const float PI = 3.14159265359;  // pi  [solid_angles.projected_hemisphere]
const float SH_C0 = 0.282094791774;  // 1/(2*sqrt(pi))  [sh.c0]
const float SH_C1 = 0.488602511903;  // sqrt(3)/(2*sqrt(pi))  [sh.c1]
const float SH_COSLOBE_C0 = 0.886226925453;  // sqrt(pi)/2  [sh.coslobe_c0]
const float SH_COSLOBE_C1 = 1.02332670795;  // sqrt(3)*sqrt(pi)/3  [sh.coslobe_c1]
const float SH_NET_FLUX_C1 = 2.04665341589;  // 2*sqrt(3)*sqrt(pi)/3  [sh.net_flux_c1]
const float SH_FLUX_FACTOR = 3.54490770181;  // 2*sqrt(pi)  [sh.flux_factor]
const float SH_L2_C0 = 0.282094791774;  // 1/(2*sqrt(pi))  [sh.l2_c0]
const float SH_L2_C1 = 0.488602511903;  // sqrt(3)/(2*sqrt(pi))  [sh.l2_c1]
const float SH_L2_C2 = 1.09254843059;  // sqrt(15)/(2*sqrt(pi))  [sh.l2_c2]
const float SH_L2_C3 = 0.315391565253;  // sqrt(5)/(4*sqrt(pi))  [sh.l2_c3]
const float SH_L2_C4 = 0.546274215296;  // sqrt(15)/(4*sqrt(pi))  [sh.l2_c4]
const float SH_L2_COSLOBE_C0 = 0.886226925453;  // sqrt(pi)/2  [sh.l2_coslobe_c0]
const float SH_L2_COSLOBE_C1 = 1.02332670795;  // sqrt(3)*sqrt(pi)/3  [sh.l2_coslobe_c1]
const float SH_L2_COSLOBE_C2 = 0.495415912201;  // sqrt(5)*sqrt(pi)/8  [sh.l2_coslobe_c2]
const float SH_L2_LOBE_C2 = 0.85808553081;  // sqrt(15)*sqrt(pi)/8  [sh.l2_lobe_c2]
const float SH_L2_LOBE_C3 = 0.2477079561;  // sqrt(5)*sqrt(pi)/16  [sh.l2_lobe_c3]
const float SH_L2_LOBE_C4 = 0.429042765405;  // sqrt(15)*sqrt(pi)/16  [sh.l2_lobe_c4]
const float INV_PI = 0.318309886184;  // 1/pi  [corrections.injection_pi.flux_factor]
const float SIDE_EVAL_SMALL = 0.4472135955;  // sqrt(5)/5  [propagation.side_eval_small]
const float SIDE_EVAL_BIG = 0.894427191;  // 2*sqrt(5)/5  [propagation.side_eval_big]
const float DX11_FRONT_SHARE = 0.5;  // 1/2  [propagation.front_share_dx11]
const float DX11_SIDE_SHARE = 0.333333333333;  // 1/3  [propagation.side_share_dx11]
const float EDGE_FACE_SOLID_ANGLE = 0.250691969473;  // -2*atan(sqrt(11)/33) + 2*atan(sqrt(19)/19)  [neighbours26.edge_face]
const float CORNER_FACE_SOLID_ANGLE = 0.172739384964;  // -2*atan(sqrt(19)/19) + atan(sqrt(11)/33) + pi/6  [neighbours26.corner_face]
const float EDGE_EVAL_BIG = 0.832050294338;  // 3*sqrt(13)/13  [neighbours26.edge_eval_big]
const float EDGE_EVAL_SMALL = 0.554700196225;  // 2*sqrt(13)/13  [neighbours26.edge_eval_small]
const float CORNER_EVAL_BIG = 0.727606875109;  // 3*sqrt(17)/17  [neighbours26.corner_eval_big]
const float CORNER_EVAL_SMALL = 0.485071250073;  // 2*sqrt(17)/17  [neighbours26.corner_eval_small]
const float INV_FOUR_PI = 0.0795774715459;  // 1/(4*pi)  [media.isotropic_phase]
const float PUBLISHED_SH_C0 = 0.282094792;  // printed in the DirectX 11 LPV implementation article; exact 1/(2*sqrt(pi)) (rounded)  [errata.dx11.sh_c0]
const float PUBLISHED_SH_C1 = 0.488602512;  // printed in the DirectX 11 LPV implementation article; exact sqrt(3)/(2*sqrt(pi)) (rounded)  [errata.dx11.sh_c1]
const float PUBLISHED_SH_COSLOBE_C0 = 0.886226925;  // printed in the DirectX 11 LPV implementation article; exact sqrt(pi)/2 (correct)  [errata.dx11.coslobe_c0]
const float PUBLISHED_SH_COSLOBE_C1 = 1.02332671;  // printed in the DirectX 11 LPV implementation article; exact sqrt(3)*sqrt(pi)/3 (rounded)  [errata.dx11.coslobe_c1]
const float PUBLISHED_PI = 3.1415926;  // printed in the DirectX 11 LPV implementation article; exact pi (truncated)  [errata.dx11.pi]
const float PUBLISHED_FRONT_FACE_SOLID_ANGLE = 0.4006696846;  // printed in the DirectX 11 LPV implementation article; exact 4*atan(sqrt(11)/33) (correct)  [errata.dx11.front_solid_angle]
const float PUBLISHED_SIDE_FACE_SOLID_ANGLE = 0.4234413544;  // printed in the DirectX 11 LPV implementation article; exact -pi/3 + 2*atan(3*sqrt(11)/11) (wrong)  [errata.dx11.side_solid_angle]
const float PUBLISHED_SIDE_EVAL_SMALL = 0.4472135;  // printed in the DirectX 11 LPV implementation article; exact sqrt(5)/5 (truncated)  [errata.dx11.side_eval_small]
const float PUBLISHED_SIDE_EVAL_BIG = 0.894427;  // printed in the DirectX 11 LPV implementation article; exact 2*sqrt(5)/5 (correct)  [errata.dx11.side_eval_big]
const float PUBLISHED_SURFEL_WEIGHT = 0.015;  // printed in the DirectX 11 LPV implementation article; exact none (not derivable)  [errata.dx11.surfel_weight]

#endif  // LPV_GENERATED_CONSTANTS
