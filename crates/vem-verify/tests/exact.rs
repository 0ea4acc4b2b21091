//! Independent checks of the exact solutions of `docs/manufactured.md`:
//! every reference value of its section 10 (typed from the specification, parsed below),
//! equilibrium and gradients by finite differences, boundary data, traction continuity, the
//! contact sign and complementarity conditions on a fine sample of Gamma_C, resultants, load
//! resultants and energies by Gauss quadrature split at the switch points.

use nalgebra::Matrix2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vem_contact::{ContactLaw, ContactNode};
use vem_mesh::generators::Rectangle;
use vem_mesh::{Point, Vector};
use vem_verify::exact::{
    all_cases, case_by_name, BodyId, ContactSet, ExactError, ExactSolution, FrictionSet, Lame,
    Side, CASE_NAMES, CONTACT_SIDES,
};

/// Section 10 of `docs/manufactured.md`, verbatim (lambda = 2, mu = 1).
const REFERENCE: &str = r##"
## M1 (lambda=2, mu=1)
body1 (1/4,1/3): ux uy sxx syy sxy fx fy =  0.016666666666666667 -0.10837490801351343  0.34084749818168194  0.34836166303003055  0.028011311054673991 -0.64098145530158851 -0.58674243989274653
body1 (7/8,3/4): ux uy sxx syy sxy fx fy =  0.020907518385835184 -0.083631093935528926 -0.73858617617777086  0.47216244953369781 -0.087594232554175918  18.044121093179872 -5.0882649201382827
body2 (1/4,-1/3): ux uy sxx syy sxy fx fy = -0.016666666666666667 -0.045791758653153239 -0.34179139070720695 -0.2835827814144139 -0.09815019994356288 -0.36667589974603296 -0.90353533788503125
body2 (7/8,-3/4): ux uy sxx syy sxy fx fy = -0.035546875 -0.043310546875 -0.45234375 -0.6609375 -0.14765625  0.13125 -0.4875
body1 Neumann side x=0 at (0,1/3): g = -0.1 -0.33456310861108774
body1 Neumann side x=1 at (1,3/4): g = -4.3530764746872634  0.36516421611325661
body2 Neumann side x=0 at (0,-1/3): g =  0.48333333333333333  0.35956310861108774
body2 Neumann side x=1 at (1,-3/4): g = -0.4875 -0.16875
Gamma_C x=1/4: sigma_nu sigma_1tau [u]_nu h0 [u]_1tau = -0.12574834424324169  0.0  0.0578125  0.0578125  0.015625
Gamma_C x=7/8: sigma_nu sigma_1tau [u]_nu h0 [u]_1tau =  0.0  0.0  0.084125536138351831  0.091015625  0.08203125
Gamma_C resultants: int sigma_nu ds = -0.12360679774997897   int sigma_1tau ds =  0.0
body1 load resultants: int f = ( 4.2860679774997897, -1.4384158614166176)   int_{x=0} g = (-0.3, -0.24467233145831581)   int_{x=1} g = (-3.9027346441664564,  0.26133899812498247)
body2 load resultants: int f = ( 0.0, -0.53912540262502454)   int_{x=0} g = ( 0.3,  0.26967233145831581)   int_{x=1} g = (-0.4, -0.11666666666666667)
body1: a(u,u) =  0.36949674465338907   ||u||_0^2 =  0.012476509794967739   |u|_1^2 =  0.11779433615398217
body2: a(u,u) =  0.066882747656103756   ||u||_0^2 =  3.5675388758912553e-3   |u|_1^2 =  0.023778888228177323
## M2 (lambda=2, mu=1)
body1 (1/4,1/3): ux uy sxx syy sxy fx fy =  0.059742514314985107 -0.159375  0.43855268734489395  0.16771384367244697  0.020169327028033216  2.7039464625066125 -3.5292658704852279
body1 (7/8,3/4): ux uy sxx syy sxy fx fy =  0.07684879486449478 -0.13220069604567053  1.0177385800960928  1.7457717334134107 -0.35914578751350157 -2.4914033600352098 -1.4379586147624882
body2 (1/4,-1/3): ux uy sxx syy sxy fx fy = -0.051409180981651774  0.013541666666666667 -0.6816082429004495 -0.72049162145022475  0.068780438139144327 -2.5789464625066125  1.4249007961814388
body2 (7/8,-3/4): ux uy sxx syy sxy fx fy = -0.06395816986449478  6.4955930168294661e-3 -0.17984795509609281 -0.12624048341341068 -0.32984891251350157  2.6007783600352098  3.5057913852375118
body1 Neumann side x=0 at (0,1/3): g = -1.3570787221094178  0.041666666666666667
body1 Neumann side x=1 at (1,3/4): g =  1.922747564417433 -0.84954004294495532
body2 Neumann side x=0 at (0,-1/3): g =  1.57930094433164 -0.027777777777777778
body2 Neumann side x=1 at (1,-3/4): g = -1.085247564417433 -0.82610254294495532
Gamma_C x=1/4: sigma_nu sigma_1tau [u]_nu h0 [u]_1tau = -1.09375 -0.20634131441743298  0.0578125  0.0578125  0.0
Gamma_C x=7/8: sigma_nu sigma_1tau [u]_nu h0 [u]_1tau = -1.0546875 -0.25  0.091015625  0.091015625  3.094490809118993e-3
Gamma_C resultants: int sigma_nu ds = -1.0833333333333333   int sigma_1tau ds = -0.21464466094067262
body1 load resultants: int f = ( 0.1364679528291557, -2.7476310729378175)   int_{x=0} g = (-1.2428090415820634,  0.0375)   int_{x=1} g = ( 1.6380711874576983, -0.60653559372884917)
body2 load resultants: int f = (-0.1864679528291557,  2.2023689270621825)   int_{x=0} g = ( 1.10947570824873, -0.020833333333333333)   int_{x=1} g = (-1.404737854124365, -0.59820226039551584)
body1: a(u,u) =  0.46032230444104041   ||u||_0^2 =  0.026238921092343523   |u|_1^2 =  0.15476272107701561
body2: a(u,u) =  0.18380773556708284   ||u||_0^2 =  3.5281472809127376e-3   |u|_1^2 =  0.076912417086689175
## M3 (lambda=2, mu=1)
body1 (1/4,1/3): ux uy sxx syy sxy fx fy =  0.016666666666666667 -0.16215277777777778  0.17951388888888889  0.025694444444444444 -0.061805555555555556 -0.23680555555555556 -3.1972222222222222
body1 (7/8,3/4): ux uy sxx syy sxy fx fy =  0.046044921875 -0.136083984375  1.1109375  1.8234375 -0.195703125 -0.4234375 -3.25625
body2 (1/4,-1/3): ux uy sxx syy sxy fx fy = -0.016666666666666667  7.9861111111111111e-3 -0.503125 -0.60625 -8.3333333333333333e-3  0.0375  1.7069444444444444
body2 (7/8,-3/4): ux uy sxx syy sxy fx fy = -0.035546875  6.1279296875e-3 -0.188671875 -0.13359375 -0.165234375  0.271875  1.66875
body1 Neumann side x=0 at (0,1/3): g = -0.1  0.052777777777777778
body1 Neumann side x=1 at (1,3/4): g =  1.1875 -0.225
body2 Neumann side x=0 at (0,-1/3): g =  0.48333333333333333 -0.027777777777777778
body2 Neumann side x=1 at (1,-3/4): g = -0.2375 -0.1921875
Gamma_C x=1/4: sigma_nu sigma_1tau [u]_nu h0 [u]_1tau = -1.09375  0.0  0.0578125  0.0578125  0.015625
Gamma_C x=7/8: sigma_nu sigma_1tau [u]_nu h0 [u]_1tau = -1.0546875  0.0  0.091015625  0.091015625  0.08203125
Gamma_C resultants: int sigma_nu ds = -1.0833333333333333   int sigma_1tau ds =  0.0
body1 load resultants: int f = (-0.33333333333333333, -3.2583333333333333)   int_{x=0} g = (-0.3,  0.045833333333333333)   int_{x=1} g = ( 0.76666666666666667, -0.15416666666666667)
body2 load resultants: int f = ( 0.0,  1.6916666666666667)   int_{x=0} g = ( 0.3, -0.020833333333333333)   int_{x=1} g = (-0.4, -0.1375)
body1: a(u,u) =  0.37955555555555556   ||u||_0^2 =  0.024245138888888889   |u|_1^2 =  0.10045138888888889
body2: a(u,u) =  0.099284722222222222   ||u||_0^2 =  1.6347222222222222e-3   |u|_1^2 =  0.024097222222222222
## M4 (lambda=2, mu=1)
body1 (1/4,1/3): ux uy sxx syy sxy fx fy =  5.5555555555555556e-3 -0.045833333333333333  0.27847222222222222  0.22361111111111111 -0.020138888888888889 -0.29930555555555556 -0.45416666666666667
body1 (7/8,3/4): ux uy sxx syy sxy fx fy =  0.036669921875 -0.0456298828125  0.566015625  0.73359375 -0.16640625 -0.4390625 -0.35
body2 (1/4,-1/3): ux uy sxx syy sxy fx fy = -0.016666666666666667 -0.052777777777777778 -0.32083333333333333 -0.24166666666666667 -0.022222222222222222 -0.025 -0.53611111111111111
body2 (7/8,-3/4): ux uy sxx syy sxy fx fy = -0.035546875 -0.043310546875 -0.45234375 -0.6609375 -0.14765625  0.13125 -0.4875
body1 Neumann side x=0 at (0,1/3): g = -0.2 -2.7777777777777778e-3
body1 Neumann side x=1 at (1,3/4): g =  0.6375 -0.2015625
body2 Neumann side x=0 at (0,-1/3): g =  0.31666666666666667  0.0
body2 Neumann side x=1 at (1,-3/4): g = -0.4875 -0.16875
Gamma_C x=1/4: sigma_nu sigma_1tau [u]_nu h0 [u]_1tau =  0.0  0.0 -4.6875e-3  0.0578125  0.015625
Gamma_C x=7/8: sigma_nu sigma_1tau [u]_nu h0 [u]_1tau =  0.0  0.0 -2.734375e-3  0.091015625  0.08203125
Gamma_C resultants: int sigma_nu ds =  0.0   int sigma_1tau ds =  0.0
body1 load resultants: int f = (-0.28333333333333333, -0.45)   int_{x=0} g = (-0.2, -8.3333333333333333e-3)   int_{x=1} g = ( 0.56666666666666667, -0.14166666666666667)
body2 load resultants: int f = ( 0.0, -0.51666666666666667)   int_{x=0} g = ( 0.3,  0.0)   int_{x=1} g = (-0.4, -0.11666666666666667)
body1: a(u,u) =  0.063652777777777778   ||u||_0^2 =  3.4048611111111111e-3   |u|_1^2 =  0.017361111111111111
body2: a(u,u) =  0.057444444444444444   ||u||_0^2 =  3.8430555555555556e-3   |u|_1^2 =  0.015486111111111111
## E1 (lambda=2, mu=1)
body1 (1/4,1/3): ux uy sxx syy sxy fx fy =  0.61237243569579452  0.86602540378443865  10.836891634560978  10.130834797665179  1.1107207345395916  30.219368432245119  57.910328793710357
body1 (7/8,3/4): ux uy sxx syy sxy fx fy =  0.27059805007309849 -0.5 -5.0677845702264539  2.1784966952714629  2.291483807404424  42.962291732906333 -58.821306987023805
body1 load resultants: int f = ( 20.0,  0.0)
body1: a(u,u) =  32.076214303540416   ||u||_0^2 =  0.5   |u|_1^2 =  17.271807701906378
## E2 (lambda=2, mu=1)
body1 (1/4,1/3): ux uy sxx syy sxy fx fy =  5.2083333333333333e-3 -9.2592592592592593e-3  0.055555555555555556 -0.055555555555555556 -0.011091820987654321  0.17766203703703704 -0.4212962962962963
body1 (7/8,3/4): ux uy sxx syy sxy fx fy = -2.2430419921875e-3  5.767822265625e-3  0.0615234375 -0.0615234375 -0.02716064453125  0.05712890625  0.357421875
body1 load resultants: int f = ( 0.0,  0.0)
body1: a(u,u) =  3.2653061224489796e-3   ||u||_0^2 =  6.0468631897203326e-5   |u|_1^2 =  3.2653061224489796e-3
## PT0a (lambda=2, mu=1)
body1 (1/4,1/3): ux uy sxx syy sxy fx fy =  0.25  0.30833333333333333  1.6  2.0  0.2  0.0  0.0
body1 (7/8,3/4): ux uy sxx syy sxy fx fy =  0.5  0.4125  1.6  2.0  0.2  0.0  0.0
body1 load resultants: int f = ( 0.0,  0.0)
body1: a(u,u) =  1.16   ||u||_0^2 =  0.27   |u|_1^2 =  0.3
## PT0b (lambda=2, mu=1)
body1 (1/4,1/3): ux uy sxx syy sxy fx fy =  0.066666666666666667 -0.033333333333333333  0.1  0.2 -0.1  0.0  0.0
body1 (7/8,3/4): ux uy sxx syy sxy fx fy =  0.025 -0.0125  0.1  0.2 -0.1  0.0  0.0
body1 Neumann side x=0 at (0,1/3): g = -0.1  0.1
body1 Neumann side x=1 at (1,3/4): g =  0.1 -0.1
body1 Neumann side y=0 at (1/4,0): g =  0.1 -0.2
body1 load resultants: int f = ( 0.0,  0.0)   int_{x=0} g = (-0.1,  0.1)   int_{x=1} g = ( 0.1, -0.1)   int_{y=0} g = ( 0.1, -0.2)
body1: a(u,u) =  0.02   ||u||_0^2 =  4.1666666666666667e-3   |u|_1^2 =  0.0125
## PTC1 (lambda=2, mu=1)
body1 (1/4,1/3): ux uy sxx syy sxy fx fy =  0.02 -0.023333333333333333 -0.02 -0.04  0.0  0.0  0.0
body1 (7/8,3/4): ux uy sxx syy sxy fx fy =  0.02 -0.0275 -0.02 -0.04  0.0  0.0  0.0
body2 (1/4,-1/3): ux uy sxx syy sxy fx fy = -0.02  0.023333333333333333 -0.02 -0.04  0.0  0.0  0.0
body2 (7/8,-3/4): ux uy sxx syy sxy fx fy = -0.02  0.0275 -0.02 -0.04  0.0  0.0  0.0
body1 Neumann side x=0 at (0,1/3): g =  0.02  0.0
body1 Neumann side x=1 at (1,3/4): g = -0.02  0.0
body2 Neumann side x=0 at (0,-1/3): g =  0.02  0.0
body2 Neumann side x=1 at (1,-3/4): g = -0.02  0.0
Gamma_C x=1/4: sigma_nu sigma_1tau [u]_nu h0 [u]_1tau = -0.04  0.0  0.04  0.04  0.04
Gamma_C x=7/8: sigma_nu sigma_1tau [u]_nu h0 [u]_1tau = -0.04  0.0  0.04  0.04  0.04
Gamma_C resultants: int sigma_nu ds = -0.04   int sigma_1tau ds =  0.0
body1 load resultants: int f = ( 0.0,  0.0)   int_{x=0} g = ( 0.02,  0.0)   int_{x=1} g = (-0.02,  0.0)
body2 load resultants: int f = ( 0.0,  0.0)   int_{x=0} g = ( 0.02,  0.0)   int_{x=1} g = (-0.02,  0.0)
body1: a(u,u) =  4.0e-4   ||u||_0^2 =  1.0333333333333333e-3   |u|_1^2 =  1.0e-4
body2: a(u,u) =  4.0e-4   ||u||_0^2 =  1.0333333333333333e-3   |u|_1^2 =  1.0e-4
## PTC1h (lambda=2, mu=1)
body1 (1/4,1/3): ux uy sxx syy sxy fx fy =  0.0  6.6666666666666667e-3 -0.02 -0.04  0.0  0.0  0.0
body1 (7/8,3/4): ux uy sxx syy sxy fx fy =  0.0  2.5e-3 -0.02 -0.04  0.0  0.0  0.0
body2 (1/4,-1/3): ux uy sxx syy sxy fx fy =  0.0 -6.6666666666666667e-3 -0.02 -0.04  0.0  0.0  0.0
body2 (7/8,-3/4): ux uy sxx syy sxy fx fy =  0.0 -2.5e-3 -0.02 -0.04  0.0  0.0  0.0
body1 Neumann side x=0 at (0,1/3): g =  0.02  0.0
body1 Neumann side x=1 at (1,3/4): g = -0.02  0.0
body2 Neumann side x=0 at (0,-1/3): g =  0.02  0.0
body2 Neumann side x=1 at (1,-3/4): g = -0.02  0.0
Gamma_C x=1/4: sigma_nu sigma_1tau [u]_nu h0 [u]_1tau = -0.04  0.0 -0.02 -0.02  0.0
Gamma_C x=7/8: sigma_nu sigma_1tau [u]_nu h0 [u]_1tau = -0.04  0.0 -0.02 -0.02  0.0
Gamma_C resultants: int sigma_nu ds = -0.04   int sigma_1tau ds =  0.0
body1 load resultants: int f = ( 0.0,  0.0)   int_{x=0} g = ( 0.02,  0.0)   int_{x=1} g = (-0.02,  0.0)
body2 load resultants: int f = ( 0.0,  0.0)   int_{x=0} g = ( 0.02,  0.0)   int_{x=1} g = (-0.02,  0.0)
body1: a(u,u) =  4.0e-4   ||u||_0^2 =  3.3333333333333333e-5   |u|_1^2 =  1.0e-4
body2: a(u,u) =  4.0e-4   ||u||_0^2 =  3.3333333333333333e-5   |u|_1^2 =  1.0e-4
## PTC2 (lambda=2, mu=1)
body1 (1/4,1/3): ux uy sxx syy sxy fx fy =  0.10333333333333333 -0.023333333333333333 -0.02 -0.04  0.25  0.0  0.0
body1 (7/8,3/4): ux uy sxx syy sxy fx fy =  0.2075 -0.0275 -0.02 -0.04  0.25  0.0  0.0
body2 (1/4,-1/3): ux uy sxx syy sxy fx fy = -0.10333333333333333  0.023333333333333333 -0.02 -0.04  0.25  0.0  0.0
body2 (7/8,-3/4): ux uy sxx syy sxy fx fy = -0.2075  0.0275 -0.02 -0.04  0.25  0.0  0.0
body1 Neumann side x=0 at (0,1/3): g =  0.02 -0.25
body1 Neumann side x=1 at (1,3/4): g = -0.02  0.25
body2 Neumann side x=0 at (0,-1/3): g =  0.02 -0.25
body2 Neumann side x=1 at (1,-3/4): g = -0.02  0.25
Gamma_C x=1/4: sigma_nu sigma_1tau [u]_nu h0 [u]_1tau = -0.04 -0.25  0.04  0.04  0.04
Gamma_C x=7/8: sigma_nu sigma_1tau [u]_nu h0 [u]_1tau = -0.04 -0.25  0.04  0.04  0.04
Gamma_C resultants: int sigma_nu ds = -0.04   int sigma_1tau ds = -0.25
body1 load resultants: int f = ( 0.0,  0.0)   int_{x=0} g = ( 0.02, -0.25)   int_{x=1} g = (-0.02,  0.25)
body2 load resultants: int f = ( 0.0,  0.0)   int_{x=0} g = ( 0.02, -0.25)   int_{x=1} g = (-0.02,  0.25)
body1: a(u,u) =  0.0629   ||u||_0^2 =  0.026866666666666667   |u|_1^2 =  0.0626
body2: a(u,u) =  0.0629   ||u||_0^2 =  0.026866666666666667   |u|_1^2 =  0.0626
## PTC3 (lambda=2, mu=1)
body1 (1/4,1/3): ux uy sxx syy sxy fx fy =  0.041666666666666667 -0.023333333333333333 -0.02 -0.04  0.125  0.0  0.0
body1 (7/8,3/4): ux uy sxx syy sxy fx fy =  0.09375 -0.0275 -0.02 -0.04  0.125  0.0  0.0
body2 (1/4,-1/3): ux uy sxx syy sxy fx fy = -0.041666666666666667  0.023333333333333333 -0.02 -0.04  0.125  0.0  0.0
body2 (7/8,-3/4): ux uy sxx syy sxy fx fy = -0.09375  0.0275 -0.02 -0.04  0.125  0.0  0.0
body1 Neumann side x=0 at (0,1/3): g =  0.02 -0.125
body1 Neumann side x=1 at (1,3/4): g = -0.02  0.125
body2 Neumann side x=0 at (0,-1/3): g =  0.02 -0.125
body2 Neumann side x=1 at (1,-3/4): g = -0.02  0.125
Gamma_C x=1/4: sigma_nu sigma_1tau [u]_nu h0 [u]_1tau = -0.04 -0.125  0.04  0.04  0.0
Gamma_C x=7/8: sigma_nu sigma_1tau [u]_nu h0 [u]_1tau = -0.04 -0.125  0.04  0.04  0.0
Gamma_C resultants: int sigma_nu ds = -0.04   int sigma_1tau ds = -0.125
body1 load resultants: int f = ( 0.0,  0.0)   int_{x=0} g = ( 0.02, -0.125)   int_{x=1} g = (-0.02,  0.125)
body2 load resultants: int f = ( 0.0,  0.0)   int_{x=0} g = ( 0.02, -0.125)   int_{x=1} g = (-0.02,  0.125)
body1: a(u,u) =  0.016025   ||u||_0^2 =  5.8416666666666667e-3   |u|_1^2 =  0.015725
body2: a(u,u) =  0.016025   ||u||_0^2 =  5.8416666666666667e-3   |u|_1^2 =  0.015725
"##;

// ---------------------------------------------------------------------------------------------
// Parsing the reference block.

/// (body, int f, [(side, int g)]) of one body.
type LoadReference = (BodyId, [f64; 2], Vec<(Side, [f64; 2])>);

/// Reference values of one case.
#[derive(Default)]
struct CaseReference {
    name: String,
    /// (body, point, [ux uy sxx syy sxy fx fy]).
    points: Vec<(BodyId, Point, [f64; 7])>,
    /// (body, side, point, g).
    tractions: Vec<(BodyId, Side, Point, [f64; 2])>,
    /// (x, [sigma_nu sigma_1tau [u]_nu h0 [u]_1tau]).
    interface: Vec<(f64, [f64; 5])>,
    /// [int sigma_nu ds, int sigma_1tau ds].
    resultants: Option<[f64; 2]>,
    loads: Vec<LoadReference>,
    /// (body, [a(u,u), ||u||_0^2, |u|_1^2]).
    energies: Vec<(BodyId, [f64; 3])>,
}

fn number(text: &str) -> f64 {
    let text = text.trim();
    match text.split_once('/') {
        Some((p, q)) => number(p) / number(q),
        None => text
            .parse()
            .unwrap_or_else(|_| panic!("not a number: {text:?}")),
    }
}

fn numbers<const N: usize>(text: &str) -> [f64; N] {
    let values: Vec<f64> = text
        .split(|c: char| c.is_whitespace() || c == ',' || c == '(' || c == ')')
        .filter(|t| !t.is_empty())
        .map(number)
        .collect();
    values
        .try_into()
        .unwrap_or_else(|v: Vec<f64>| panic!("expected {N} numbers, got {v:?} in {text:?}"))
}

/// "(1/4,-1/3)" -> the point.
fn point(text: &str) -> Point {
    let [x, y] = numbers::<2>(text);
    Point::new(x, y)
}

fn body(text: &str) -> BodyId {
    match text {
        "body1" => BodyId::One,
        "body2" => BodyId::Two,
        _ => panic!("unknown body {text:?}"),
    }
}

/// "x=0" -> Left, "x=1" -> Right, "y=0" -> Bottom (the unit-square sides of section 10).
fn side(text: &str) -> Side {
    match text.trim() {
        "x=0" => Side::Left,
        "x=1" => Side::Right,
        "y=0" => Side::Bottom,
        other => panic!("unknown side {other:?}"),
    }
}

fn after_equals(line: &str) -> &str {
    line.split_once('=').map(|(_, rest)| rest).expect("a '='")
}

fn parse_reference() -> Vec<CaseReference> {
    let mut cases: Vec<CaseReference> = Vec::new();
    for line in REFERENCE.lines().map(str::trim).filter(|l| !l.is_empty()) {
        if let Some(rest) = line.strip_prefix("## ") {
            cases.push(CaseReference {
                name: rest.split_whitespace().next().unwrap().to_owned(),
                ..Default::default()
            });
            continue;
        }
        let case = cases.last_mut().expect("a case header first");
        if let Some(rest) = line.strip_prefix("Gamma_C resultants:") {
            let parts: Vec<&str> = rest.split('=').collect();
            let normal = number(parts[1].split_whitespace().next().unwrap());
            let tangential = number(parts[2]);
            case.resultants = Some([normal, tangential]);
        } else if let Some(rest) = line.strip_prefix("Gamma_C x=") {
            let (x, values) = rest.split_once(':').unwrap();
            case.interface
                .push((number(x), numbers::<5>(after_equals(values))));
        } else if line.contains("load resultants") {
            let (head, rest) = line.split_once(':').unwrap();
            let body = body(head.split_whitespace().next().unwrap());
            let mut force = None;
            let mut sides = Vec::new();
            for piece in rest.split("int").map(str::trim).filter(|p| !p.is_empty()) {
                let (key, value) = piece.split_once(" = ").unwrap();
                let value = numbers::<2>(value);
                match key.trim() {
                    "f" => force = Some(value),
                    key => {
                        let inside = key.trim_start_matches("_{").split('}').next().unwrap();
                        sides.push((side(inside), value));
                    }
                }
            }
            case.loads.push((body, force.expect("int f"), sides));
        } else if line.contains("a(u,u)") {
            let body = body(line.split(':').next().unwrap());
            let parts: Vec<&str> = line.split('=').collect();
            let first = |p: &str| number(p.split_whitespace().next().unwrap());
            case.energies
                .push((body, [first(parts[1]), first(parts[2]), first(parts[3])]));
        } else if line.contains("Neumann side") {
            // "body1 Neumann side x=0 at (0,1/3): g = a b"
            let words: Vec<&str> = line.split_whitespace().collect();
            let (head, values) = line.split_once(':').unwrap();
            let at = head.split("at").nth(1).unwrap();
            case.tractions.push((
                body(words[0]),
                side(words[3]),
                point(at),
                numbers::<2>(after_equals(values)),
            ));
        } else {
            // "body1 (1/4,1/3): ux uy sxx syy sxy fx fy = v1 ... v7"
            let (head, values) = line.split_once(':').unwrap();
            let (name, at) = head.split_once(' ').unwrap();
            case.points
                .push((body(name), point(at), numbers::<7>(after_equals(values))));
        }
    }
    cases
}

// ---------------------------------------------------------------------------------------------
// Tolerances and quadrature.

/// `|computed - expected| <= 1e-13 |expected| + 1e-15`.
fn assert_close(computed: f64, expected: f64, what: &str) {
    assert!(
        (computed - expected).abs() <= 1e-13 * expected.abs() + 1e-15,
        "{what}: computed {computed:e}, expected {expected:e}, difference {:e}",
        computed - expected
    );
}

/// A quadrature result: `|computed - expected| <= 1e-13 |expected| + 1e-15 (1 + magnitude)`
/// with `magnitude` the integral of the absolute value of the integrand (the size of the
/// round-off of the sum).
fn assert_close_quadrature(computed: f64, expected: f64, magnitude: f64, what: &str) {
    assert!(
        (computed - expected).abs() <= 1e-13 * expected.abs() + 1e-15 * (1.0 + magnitude),
        "{what}: computed {computed:e}, expected {expected:e}, difference {:e}",
        computed - expected
    );
}

/// The round-off of stresses computed from gradients: sums of terms ~ lambda grad u that
/// cancel (sigma_yy on Gamma_C) lose about eps (lambda + 2 mu).
fn stress_round_off(lame: Lame) -> f64 {
    1e-15 * (lame.lambda() + 2.0 * lame.mu())
}

/// Gauss-Legendre nodes and weights on (-1, 1), by Newton's method on P_n.
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut derivative = 1.0;
            for _ in 0..100 {
                // P_n(x) and P_n'(x) by the three-term recurrence.
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let k = k as f64;
                    (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
                }
                derivative = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let step = p1 / derivative;
                x -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * derivative * derivative))
        })
        .collect()
}

/// Quadrature points and weights on [a, b]: `pieces` equal sub-intervals of every interval
/// between consecutive `breaks`, 12 Gauss points each (exact to degree 23 on each piece).
fn rule_1d(breaks: &[f64], pieces: usize) -> Vec<(f64, f64)> {
    let gauss = gauss_legendre(12);
    let mut rule = Vec::new();
    for pair in breaks.windows(2) {
        let h = (pair[1] - pair[0]) / pieces as f64;
        for k in 0..pieces {
            let a = pair[0] + k as f64 * h;
            rule.extend(
                gauss
                    .iter()
                    .map(|&(t, w)| (a + 0.5 * h * (t + 1.0), 0.5 * h * w)),
            );
        }
    }
    rule
}

/// The switch point of a contact solution (contact/separation or stick/slip), if any.
fn switch_point(solution: &dyn ExactSolution) -> Option<f64> {
    let sets = solution.contact()?.expected_sets()?;
    if let ContactSet::Split { switch_point, .. } = sets.contact {
        return Some(switch_point);
    }
    match sets.friction {
        Some(FrictionSet::Split { switch_point, .. }) => Some(switch_point),
        _ => None,
    }
}

/// Abscissae where the x-interval [a, b] must be split: its ends and the switch point (the
/// integrands are only piecewise smooth across it).
fn x_breaks(solution: &dyn ExactSolution, a: f64, b: f64) -> Vec<f64> {
    let mut breaks = vec![a];
    breaks.extend(switch_point(solution).filter(|&s| a < s && s < b));
    breaks.push(b);
    breaks
}

/// A 2D tensor rule on the domain of `body`, split at the switch line.
fn rule_2d(solution: &dyn ExactSolution, body: BodyId) -> Vec<(Point, f64)> {
    let rect = solution.domain(body);
    let xs = rule_1d(&x_breaks(solution, rect.min.x, rect.max.x), 4);
    let ys = rule_1d(&[rect.min.y, rect.max.y], 4);
    xs.iter()
        .flat_map(|&(x, wx)| ys.iter().map(move |&(y, wy)| (Point::new(x, y), wx * wy)))
        .collect()
}

/// A rule along `side` of `rect` (points and weights, the side's length element included).
fn rule_side(solution: &dyn ExactSolution, rect: &Rectangle, side: Side) -> Vec<(Point, f64)> {
    match side {
        Side::Left | Side::Right => {
            let x = if side == Side::Left {
                rect.min.x
            } else {
                rect.max.x
            };
            rule_1d(&[rect.min.y, rect.max.y], 2)
                .into_iter()
                .map(|(y, w)| (Point::new(x, y), w))
                .collect()
        }
        Side::Bottom | Side::Top => {
            let y = if side == Side::Bottom {
                rect.min.y
            } else {
                rect.max.y
            };
            rule_1d(&x_breaks(solution, rect.min.x, rect.max.x), 2)
                .into_iter()
                .map(|(x, w)| (Point::new(x, y), w))
                .collect()
        }
    }
}

fn reference_cases() -> Vec<(CaseReference, Box<dyn ExactSolution>)> {
    let cases: Vec<_> = parse_reference()
        .into_iter()
        .map(|reference| {
            let solution = case_by_name(&reference.name, Lame::default()).unwrap();
            assert_eq!(solution.name(), reference.name);
            (reference, solution)
        })
        .collect();
    let names: Vec<&str> = cases.iter().map(|(r, _)| r.name.as_str()).collect();
    assert_eq!(
        names, CASE_NAMES,
        "section 10 lists every case once, in order"
    );
    cases
}

/// Materials for the identities that hold for every lambda, mu.
fn materials() -> [Lame; 3] {
    [
        Lame::default(),
        Lame::try_new(7.5, 0.4).unwrap(),
        Lame::try_new(1e4, 3.0).unwrap(),
    ]
}

// ---------------------------------------------------------------------------------------------
// Section 10, point values.

#[test]
fn section_10_point_values() {
    let mut checked = 0;
    for (reference, solution) in reference_cases() {
        let name = &reference.name;
        for &(body, x, expected) in &reference.points {
            let u = solution.displacement(body, x);
            let s = solution.stress(body, x);
            let f = solution.body_force(body, x);
            let computed = [u.x, u.y, s[(0, 0)], s[(1, 1)], s[(0, 1)], f.x, f.y];
            let labels = ["ux", "uy", "sxx", "syy", "sxy", "fx", "fy"];
            for k in 0..7 {
                let what = format!("{name} {body:?} at {x}: {}", labels[k]);
                assert_close(computed[k], expected[k], &what);
            }
            assert_eq!(s[(0, 1)], s[(1, 0)], "{name}: symmetric stress");
            checked += 1;
        }
        for &(body, side, x, expected) in &reference.tractions {
            assert!(
                solution.neumann_sides(body).contains(&side),
                "{name}: {side:?} of {body:?} is a Neumann side"
            );
            let g = solution.traction(body, side, x);
            assert_close(g.x, expected[0], &format!("{name} {body:?} {side:?} g_x"));
            assert_close(g.y, expected[1], &format!("{name} {body:?} {side:?} g_y"));
            checked += 1;
        }
        for &(x, expected) in &reference.interface {
            let contact = solution.contact().expect("a contact case");
            let v = contact.interface_values(x);
            let computed = [
                v.sigma_nu,
                v.sigma_1tau,
                v.normal_jump,
                v.initial_gap,
                v.tangential_jump,
            ];
            let labels = ["sigma_nu", "sigma_1tau", "[u]_nu", "h0", "[u]_1tau"];
            for k in 0..5 {
                assert_close(
                    computed[k],
                    expected[k],
                    &format!("{name} x={x}: {}", labels[k]),
                );
            }
            checked += 1;
        }
        if let Some([normal, tangential]) = reference.resultants {
            let exact = solution
                .contact()
                .and_then(|c| c.reference_resultants())
                .expect("closed-form resultants");
            assert_close(exact.normal, normal, &format!("{name} int sigma_nu"));
            assert_close(
                exact.tangential,
                tangential,
                &format!("{name} int sigma_1tau"),
            );
        }
    }
    // 12 cases: 2 or 4 body points each, plus Neumann points and interface points.
    // Two-body cases: 4 points, 4 Neumann points, 2 interface points; one-body cases: 2
    // points; PT0b: 3 Neumann points.
    assert_eq!(checked, 8 * (4 + 4 + 2) + 4 * 2 + 3);
}

// ---------------------------------------------------------------------------------------------
// Section 10, integrals by quadrature.

/// The integrals of the components of `integrand` by `rule`, and of their absolute values.
fn integrate<P: Copy, const N: usize>(
    rule: &[(P, f64)],
    integrand: impl Fn(P) -> [f64; N],
) -> ([f64; N], [f64; N]) {
    let (mut integral, mut magnitude) = ([0.0; N], [0.0; N]);
    for &(x, w) in rule {
        for (k, value) in integrand(x).into_iter().enumerate() {
            integral[k] += w * value;
            magnitude[k] += w * value.abs();
        }
    }
    (integral, magnitude)
}

/// `int sigma_nu ds`, `int sigma_1tau ds` over Gamma_C by quadrature split at the switch
/// point, and the integrals of their absolute values.
fn interface_resultants(solution: &dyn ExactSolution) -> ([f64; 2], [f64; 2]) {
    let contact = solution.contact().expect("a contact case");
    let rect = solution.domain(BodyId::One);
    let rule = rule_1d(&x_breaks(solution, rect.min.x, rect.max.x), 2);
    integrate(&rule, |x| {
        let v = contact.interface_values(x);
        [v.sigma_nu, v.sigma_1tau]
    })
}

#[test]
fn section_10_interface_resultants_by_quadrature() {
    for (reference, solution) in reference_cases() {
        let name = &reference.name;
        let Some(expected) = reference.resultants else {
            assert!(solution.contact().is_none(), "{name}");
            continue;
        };
        let (computed, magnitude) = interface_resultants(solution.as_ref());
        for k in 0..2 {
            let what = format!("{name} {}", ["int sigma_nu ds", "int sigma_1tau ds"][k]);
            assert_close_quadrature(computed[k], expected[k], magnitude[k], &what);
        }
    }
}

#[test]
fn section_10_load_resultants_by_quadrature() {
    let mut checked = 0;
    for (reference, solution) in reference_cases() {
        let name = &reference.name;
        for (body, force, sides) in &reference.loads {
            let body = *body;
            let (int_f, magnitude) = integrate(&rule_2d(solution.as_ref(), body), |x| {
                solution.body_force(body, x).into()
            });
            for k in 0..2 {
                let what = format!("{name} {body:?} int f_{}", ["x", "y"][k]);
                assert_close_quadrature(int_f[k], force[k], magnitude[k], &what);
            }
            let mut listed: Vec<Side> = sides.iter().map(|(s, _)| *s).collect();
            let mut neumann = solution.neumann_sides(body);
            listed.sort_by_key(|s| s.name());
            neumann.sort_by_key(|s| s.name());
            assert_eq!(
                listed, neumann,
                "{name} {body:?}: section 10 lists every Neumann side"
            );
            let rect = solution.domain(body);
            for &(side, expected) in sides {
                let rule = rule_side(solution.as_ref(), &rect, side);
                let (int_g, magnitude) =
                    integrate(&rule, |x| solution.traction(body, side, x).into());
                for k in 0..2 {
                    let what = format!("{name} {body:?} {side:?} int g_{}", ["x", "y"][k]);
                    assert_close_quadrature(int_g[k], expected[k], magnitude[k], &what);
                }
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 8 * 2 + 4);
}

#[test]
fn section_10_energies_by_quadrature() {
    let mut checked = 0;
    for (reference, solution) in reference_cases() {
        assert_eq!(reference.energies.len(), solution.bodies().len());
        for &(body, expected) in &reference.energies {
            let (computed, magnitude) = integrate(&rule_2d(solution.as_ref(), body), |x| {
                let g = solution.gradient(body, x);
                let s = solution.stress(body, x);
                [
                    s.component_mul(&g).sum(),
                    solution.displacement(body, x).norm_squared(),
                    g.norm_squared(),
                ]
            });
            for k in 0..3 {
                let what = format!(
                    "{} {body:?} {}",
                    reference.name,
                    ["a(u,u)", "||u||_0^2", "|u|_1^2"][k]
                );
                assert_close_quadrature(computed[k], expected[k], magnitude[k], &what);
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 8 * 2 + 4);
}

// ---------------------------------------------------------------------------------------------
// Identities for several materials.

/// Random points strictly inside the domain of `body` (away from the boundary by 1e-3).
fn interior_points(rect: &Rectangle, rng: &mut ChaCha8Rng, count: usize) -> Vec<Point> {
    (0..count)
        .map(|_| {
            Point::new(
                rng.gen_range(rect.min.x + 1e-3..rect.max.x - 1e-3),
                rng.gen_range(rect.min.y + 1e-3..rect.max.y - 1e-3),
            )
        })
        .collect()
}

#[test]
fn equilibrium_by_finite_differences_of_the_stress() {
    let mut rng = ChaCha8Rng::seed_from_u64(20240601);
    let h = 1e-5;
    for lame in materials() {
        for solution in all_cases(lame) {
            for &body in solution.bodies() {
                let rect = solution.domain(body);
                for x in interior_points(&rect, &mut rng, 200) {
                    let s = |dx: f64, dy: f64| solution.stress(body, x + Vector::new(dx, dy));
                    let ds_dx = (s(h, 0.0) - s(-h, 0.0)) / (2.0 * h);
                    let ds_dy = (s(0.0, h) - s(0.0, -h)) / (2.0 * h);
                    let div =
                        Vector::new(ds_dx[(0, 0)] + ds_dy[(0, 1)], ds_dx[(1, 0)] + ds_dy[(1, 1)]);
                    let f = solution.body_force(body, x);
                    let error = (div + f).amax();
                    assert!(
                        error <= 1e-6 * f.amax().max(1.0),
                        "{} {body:?} lambda={} mu={} at {x}: -div sigma - f = {error:e} (|f| = {:e})",
                        solution.name(),
                        lame.lambda(),
                        lame.mu(),
                        f.amax()
                    );
                }
            }
        }
    }
}

#[test]
fn gradient_by_finite_differences_of_the_displacement() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let h = 1e-5;
    for lame in materials() {
        for solution in all_cases(lame) {
            for &body in solution.bodies() {
                let rect = solution.domain(body);
                for x in interior_points(&rect, &mut rng, 200) {
                    let u = |dx: f64, dy: f64| solution.displacement(body, x + Vector::new(dx, dy));
                    let du_dx = (u(h, 0.0) - u(-h, 0.0)) / (2.0 * h);
                    let du_dy = (u(0.0, h) - u(0.0, -h)) / (2.0 * h);
                    let fd = Matrix2::from_columns(&[du_dx, du_dy]);
                    let g = solution.gradient(body, x);
                    let error = (fd - g).amax();
                    assert!(
                        error <= 1e-7 * (1.0 + g.amax()),
                        "{} {body:?} at {x}: gradient - finite differences = {error:e}",
                        solution.name()
                    );
                    assert_eq!(solution.stress(body, x), lame.stress(&g));
                }
            }
        }
    }
}

#[test]
fn sides_partition_the_boundary() {
    for solution in all_cases(Lame::default()) {
        for &body in solution.bodies() {
            let mut sides: Vec<Side> = solution.dirichlet_sides(body);
            assert!(!sides.is_empty(), "{}: clamped somewhere", solution.name());
            sides.extend(solution.neumann_sides(body));
            if solution.contact().is_some() {
                sides.extend(
                    CONTACT_SIDES
                        .iter()
                        .filter(|(b, _)| *b == body)
                        .map(|(_, s)| *s),
                );
            }
            sides.sort_by_key(|s| s.name());
            let mut all = Side::ALL.to_vec();
            all.sort_by_key(|s| s.name());
            assert_eq!(sides, all, "{} {body:?}", solution.name());
        }
    }
}

/// Dirichlet data: zero for every case but PT0a (data = the affine field) and the patch tests
/// PTC1, PTC2, PTC3 pushed by `u_1(x, 1) = (e, -d)`, `u_2(x, -1) = (-e, d)`.
#[test]
fn dirichlet_data() {
    let pushed = |name: &str| -> Option<(f64, f64)> {
        match name {
            "PTC1" => Some((1.0 / 50.0, 3.0 / 100.0)),
            "PTC2" => Some((1.0 / 4.0 + 1.0 / 50.0, 3.0 / 100.0)),
            "PTC3" => Some((1.0 / 8.0, 3.0 / 100.0)),
            _ => None,
        }
    };
    for solution in all_cases(Lame::default()) {
        let name = solution.name();
        for &body in solution.bodies() {
            let rect = solution.domain(body);
            for side in solution.dirichlet_sides(body) {
                for (x, _) in rule_side(solution.as_ref(), &rect, side) {
                    let u = solution.displacement(body, x);
                    let expected = match (name, pushed(name), body) {
                        ("PT0a", _, _) => Vector::new(
                            (1.0 + 2.0 * x.x + 3.0 * x.y) / 10.0,
                            (2.0 - x.x + 4.0 * x.y) / 10.0,
                        ),
                        (_, Some((e, d)), BodyId::One) => Vector::new(e, -d),
                        (_, Some((e, d)), BodyId::Two) => Vector::new(-e, d),
                        (_, None, _) => Vector::zeros(),
                    };
                    assert!(
                        (u - expected).amax() <= 1e-15,
                        "{name} {body:?} {side:?} at {x}: u = {u:?}, expected {expected:?}"
                    );
                }
            }
        }
    }
}

/// Family A tractions are polynomials of degree <= 2 in y on the lateral sides, so 2-point
/// Gauss integrates them against the linear VEM trace exactly.
#[test]
fn lateral_tractions_are_quadratic_in_y() {
    for solution in all_cases(Lame::default()) {
        for &body in solution.bodies() {
            let rect = solution.domain(body);
            for side in solution.neumann_sides(body) {
                let [a, b] = side.end_points(&rect);
                let g = |t: f64| solution.traction(body, side, a + (b - a) * t);
                // The third finite difference of a quadratic vanishes.
                let third = g(1.0) - g(2.0 / 3.0) * 3.0 + g(1.0 / 3.0) * 3.0 - g(0.0);
                assert!(
                    third.amax() <= 1e-13,
                    "{} {body:?} {side:?}",
                    solution.name()
                );
            }
        }
    }
}

#[test]
fn traction_continuity_across_the_interface() {
    for lame in materials() {
        for solution in all_cases(lame) {
            if solution.contact().is_none() {
                continue;
            }
            for i in 0..=1000 {
                let x = Point::new(i as f64 / 1000.0, 0.0);
                let (s1, s2) = (
                    solution.stress(BodyId::One, x),
                    solution.stress(BodyId::Two, x),
                );
                // sigma_1 nu_1 = -sigma_2 nu_2 with nu_1 = -nu_2 = (0, -1).
                let t1 = solution.traction(BodyId::One, Side::Bottom, x);
                let t2 = solution.traction(BodyId::Two, Side::Top, x);
                let scale = stress_round_off(lame);
                assert!(
                    (t1 + t2).amax() <= scale,
                    "{} (lambda={}) at {x}: {:e} > {scale:e}",
                    solution.name(),
                    lame.lambda(),
                    (t1 + t2).amax()
                );
                assert!((s1[(1, 1)] - s2[(1, 1)]).abs() <= scale);
                assert!((s1[(0, 1)] - s2[(0, 1)]).abs() <= scale);
            }
        }
    }
}

/// The hypotheses of the argument of `docs/manufactured.md`, section 1, on 4001 points of Gamma_C
/// (both end points included), and the expected sets against the exact statuses.
#[test]
fn contact_sign_conditions_and_complementarity() {
    let mut contact_cases = 0;
    for lame in materials() {
        for solution in all_cases(lame) {
            let Some(contact) = solution.contact() else {
                continue;
            };
            contact_cases += 1;
            let name = solution.name();
            let sets = contact
                .expected_sets()
                .expect("built-in cases list their sets");
            for i in 0..=4000 {
                let x = i as f64 / 4000.0;
                let v = contact.interface_values(x);
                let tol = stress_round_off(lame);
                let here = format!(
                    "{name} (lambda={}, mu={}) at x = {x}",
                    lame.lambda(),
                    lame.mu()
                );
                assert!(v.sigma_nu <= tol, "{here}: sigma_nu = {:e} > 0", v.sigma_nu);
                assert!(v.gap() >= -1e-15, "{here}: penetration {:e}", v.gap());
                assert!(
                    (v.sigma_nu * v.gap()).abs() <= tol,
                    "{here}: sigma_nu ([u]_nu - h0) = {:e}",
                    v.sigma_nu * v.gap()
                );
                let law = contact.law();
                // g_F at x: the nodal bound of a node of unit tributary measure there.
                let unit_node = ContactNode::<2> {
                    pair: 0,
                    body_a: 0,
                    vertex_a: 0,
                    body_b: Some(1),
                    vertex_b: Some(0),
                    position: Point::new(x, 0.0),
                    normal: Vector::new(0.0, -1.0),
                    tributary_measure: 1.0,
                    geometric_gap: 0.0,
                    initial_gap: 0.0,
                };
                let bound = law.friction_bounds(&[unit_node], None).expect("bound")[0];
                match law.name() {
                    "frictionless" => {
                        assert!(
                            v.sigma_1tau.abs() <= tol,
                            "{here}: sigma_1tau = {:e}",
                            v.sigma_1tau
                        );
                        assert!(sets.friction.is_none());
                    }
                    "tresca" => {
                        let g = bound;
                        assert!(v.sigma_1tau.abs() <= g + tol, "{here}: |sigma_1tau| > g_F");
                        if v.sigma_1tau.abs() < g - tol {
                            assert!(
                                v.tangential_jump.abs() <= 1e-15,
                                "{here}: slip while |sigma_1tau| < g_F"
                            );
                        }
                        if v.tangential_jump != 0.0 {
                            // sigma_1tau = -beta [u]_1tau with beta > 0: = -g_F sign([u]_1tau).
                            let expected = -g * v.tangential_jump.signum();
                            assert!(
                                (v.sigma_1tau - expected).abs() <= tol,
                                "{here}: slip against friction"
                            );
                        }
                        // Exact statuses. Next to a switch point the margins g_F - |sigma_1tau|
                        // fall below round-off, so strictness is asserted on the expected sets.
                        let set = sets.friction.expect("Tresca cases list stick/slip");
                        let slips = match set {
                            FrictionSet::Split {
                                switch_point,
                                stick_up_to,
                                slip_from,
                            } => {
                                assert!(stick_up_to < switch_point && switch_point < slip_from);
                                x > switch_point
                            }
                            set => set.expects_slip(x).unwrap(),
                        };
                        if slips {
                            assert!(
                                v.tangential_jump != 0.0 && (v.sigma_1tau.abs() - g).abs() <= tol,
                                "{here}: not slipping"
                            );
                        } else {
                            assert!(v.tangential_jump == 0.0, "{here}: not sticking");
                        }
                        if let Some(expected) = set.expects_slip(x) {
                            assert_eq!(slips, expected, "{here}: friction set");
                            if !expected {
                                assert!(v.sigma_1tau.abs() < g, "{here}: no stick margin");
                            }
                        }
                    }
                    other => panic!("{here}: the built-in cases have no law {}", other),
                }
                // Exact statuses: strict complementarity except at the switch point.
                let active = match sets.contact {
                    ContactSet::Split {
                        switch_point,
                        active_up_to,
                        inactive_from,
                    } => {
                        assert!(active_up_to < switch_point && switch_point < inactive_from);
                        x < switch_point
                    }
                    set => set.expects_active(x).unwrap(),
                };
                // Next to x_c the pressure (x_c - x)^4 and the opening (x - x_c)^5 are below
                // round-off: sigma_nu <= 0 and gap >= 0 are asserted above, strictness on the
                // expected sets.
                if active {
                    assert!(v.gap().abs() <= 1e-15, "{here}: not in contact");
                } else {
                    assert!(v.sigma_nu.abs() <= tol, "{here}: pressure where separated");
                }
                if let Some(expected) = sets.contact.expects_active(x) {
                    assert_eq!(active, expected, "{here}: contact set");
                    if expected {
                        assert!(v.sigma_nu < -tol, "{here}: no pressure margin");
                    } else {
                        assert!(v.gap() > 0.0, "{here}: no gap margin");
                    }
                }
            }
            // The closed-form resultants match the field.
            let exact = contact.reference_resultants().unwrap();
            let (computed, magnitude) = interface_resultants(solution.as_ref());
            let what = format!(
                "{name} (lambda={}, mu={}) resultants",
                lame.lambda(),
                lame.mu()
            );
            for (k, exact) in [exact.normal, exact.tangential].into_iter().enumerate() {
                // Where a stress vanishes exactly it is computed to stress round-off.
                let tol = 1e-13 * magnitude[k] + stress_round_off(lame);
                assert!((computed[k] - exact).abs() <= tol, "{what}: {computed:?}");
            }
        }
    }
    assert_eq!(contact_cases, 3 * 8);
}

/// Family A margins of section 8 in pressure and gap: M3 pressure >= 1, M4 gap >= 1/20,
/// patch tests pressure (lambda + 2 mu)/100.
#[test]
fn full_contact_and_no_contact_margins() {
    let lame = Lame::default();
    let m3 = case_by_name("M3", lame).unwrap();
    let m4 = case_by_name("M4", lame).unwrap();
    for i in 0..=1000 {
        let x = i as f64 / 1000.0;
        assert!(m3.contact().unwrap().interface_values(x).sigma_nu <= -1.0);
        let v = m4.contact().unwrap().interface_values(x);
        assert!(v.gap() >= 1.0 / 20.0 - 1e-16);
        // [u]_nu = h0 - q4 = (x^2 - x)/40 (section 10: -4.6875e-3 at x = 1/4; the "-x/40"
        // of section 5 drops the x^2 term).
        assert_close(
            v.normal_jump,
            (x * x - x) / 40.0,
            "M4 [u]_nu = (x^2 - x)/40",
        );
    }
    for name in ["PTC1", "PTC1h", "PTC2", "PTC3"] {
        let v = case_by_name(name, lame)
            .unwrap()
            .contact()
            .unwrap()
            .interface_values(0.3);
        assert_close(v.sigma_nu, -0.04, name);
    }
}

/// E2 does not depend on lambda (div u = 0); the other cases' body force does.
#[test]
fn lambda_dependence() {
    let (soft, stiff) = (
        Lame::try_new(2.0, 1.0).unwrap(),
        Lame::try_new(1e6, 1.0).unwrap(),
    );
    let x = Point::new(0.3, 0.7);
    let (a, b) = (
        case_by_name("E2", soft).unwrap(),
        case_by_name("E2", stiff).unwrap(),
    );
    assert_eq!(
        a.displacement(BodyId::One, x),
        b.displacement(BodyId::One, x)
    );
    assert!((a.stress(BodyId::One, x) - b.stress(BodyId::One, x)).amax() <= 1e-9);
    assert_eq!(a.body_force(BodyId::One, x), b.body_force(BodyId::One, x));
    assert!(a.gradient(BodyId::One, x).trace().abs() <= 1e-17);
    for name in ["M1", "M2", "M3", "M4", "E1"] {
        let (a, b) = (
            case_by_name(name, soft).unwrap(),
            case_by_name(name, stiff).unwrap(),
        );
        let ratio = b.body_force(BodyId::One, x).norm() / a.body_force(BodyId::One, x).norm();
        assert!(ratio > 1e3, "{name}: f grows like lambda (ratio {ratio:e})");
    }
}

// ---------------------------------------------------------------------------------------------
// The registry and the small types.

#[test]
fn registry_names_and_lookup() {
    let cases = all_cases(Lame::default());
    let names: Vec<&str> = cases.iter().map(|c| c.name()).collect();
    assert_eq!(names, CASE_NAMES);
    assert_eq!(
        case_by_name("ptc1H", Lame::default()).unwrap().name(),
        "PTC1h"
    );
    match case_by_name("M5", Lame::default()) {
        Err(ExactError::UnknownCase { name, known }) => {
            assert_eq!(name, "M5");
            assert!(known.contains("PTC3"));
        }
        other => panic!(
            "expected UnknownCase, got {:?}",
            other.map(|c| c.name().to_owned())
        ),
    }
    for case in &cases {
        let contact =
            matches!(case.name(), "M1" | "M2" | "M3" | "M4") || case.name().starts_with("PTC");
        assert_eq!(case.contact().is_some(), contact, "{}", case.name());
        assert_eq!(case.bodies().len(), if contact { 2 } else { 1 });
        assert_eq!(case.lame(), Lame::default());
    }
}

#[test]
fn small_types_validate_their_input() {
    assert!(matches!(
        Lame::try_new(1.0, 0.0),
        Err(ExactError::InvalidLame { .. })
    ));
    assert!(matches!(
        Lame::try_new(-2.0, 1.0),
        Err(ExactError::InvalidLame { .. })
    ));
    assert!(matches!(
        Lame::try_new(f64::INFINITY, 1.0),
        Err(ExactError::InvalidLame { .. })
    ));
    assert!(Lame::try_new(-0.5, 1.0).is_ok());
    assert_eq!(Side::from_name("bottom").unwrap(), Side::Bottom);
    assert!(matches!(
        Side::from_name("front"),
        Err(ExactError::UnknownSide { .. })
    ));
    assert_eq!(BodyId::from_index(1).unwrap(), BodyId::Two);
    assert!(matches!(
        BodyId::from_index(2),
        Err(ExactError::UnknownBody { index: 2 })
    ));
    for side in Side::ALL {
        let [a, b] = side.end_points(&Rectangle::unit_square());
        // Counter-clockwise: the outward normal is the tangent turned clockwise.
        let t = b - a;
        assert_eq!(Vector::new(t.y, -t.x), side.outward_normal());
    }
}

#[test]
#[should_panic(expected = "the exact solution E1 has a single body")]
fn single_body_solution_rejects_body_two() {
    let e1 = case_by_name("E1", Lame::default()).unwrap();
    e1.displacement(BodyId::Two, Point::new(0.5, 0.5));
}
