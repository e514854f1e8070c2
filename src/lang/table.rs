//! The one table of command definitions: name (with minimal abbreviation in upper case),
//! parameters, help text, sub-keywords and the builder that reads the typed parameters.
//! Help, completion and `doc/commands.md` are all generated from this table.

use super::args::{Args, ParseError};
use super::command::*;
use super::keyword::{Keyword, kw};
use super::lexer::Token;
use super::script::{self, ScriptCmd};

/// Reads the parameters of one command from the cursor.
pub type Builder = fn(&mut Args) -> Result<Command, ParseError>;

pub struct CommandDef {
    /// Name with the minimal abbreviation in upper case.
    pub name: &'static str,
    /// Parameters as in Appendix B (lower case = numbers, upper case = keywords).
    pub syntax: &'static str,
    pub help: &'static str,
    /// Keywords accepted after the command (for completion and the reference).
    pub keywords: &'static [&'static str],
    /// Whether the command is from Lian 1994 Appendix B (false: added by trubal).
    pub appendix_b: bool,
    pub build: Builder,
}

macro_rules! def {
    ($name:expr, $syntax:expr, $kws:expr, $b:expr, $build:expr, $help:expr) => {
        CommandDef {
            name: $name,
            syntax: $syntax,
            help: $help,
            keywords: $kws,
            appendix_b: $b,
            build: $build,
        }
    };
}

/// The largest FRAction accepted. At FRAction 1 a Hertz contact at 10 m/s lasts about 3
/// steps (doc/timestep.md); at 10 it lasts a third of one, and contacts are stepped over.
/// Up to 10, the blow-up tests (FRAction 3, 5, 10) can still show what an unstable step does.
pub const MAX_FRACTION: f64 = 10.0;

pub const PRINT_ITEMS: &[Keyword<PrintItem>] = &[
    kw("Balls", PrintItem::Balls),
    kw("BONds", PrintItem::Bonds),
    kw("CHist", PrintItem::Chist),
    kw("CLUsters", PrintItem::Clusters),
    kw("Contacts", PrintItem::Contacts(ContactsFilter::Loaded)),
    kw("ENErgy", PrintItem::Energy),
    kw("ENTries", PrintItem::Entries),
    kw("Grid", PrintItem::Grid),
    kw("HIStory", PrintItem::History),
    kw("Info", PrintItem::Info),
    kw("Map", PrintItem::Map),
    kw("Partitions", PrintItem::Partitions),
    kw("SETtings", PrintItem::Settings),
    kw("Stress", PrintItem::Stress),
    kw("Walls", PrintItem::Walls),
    kw("GROup", PrintItem::Range),
    kw("RANge", PrintItem::Range),
];

const CONTACT_FILTERS: &[Keyword<ContactsFilter>] = &[
    kw("All", ContactsFilter::All),
    kw("Gap", ContactsFilter::Gap),
];

pub const PLOT_ITEMS: &[Keyword<PlotItem>] = &[
    kw("BALl", PlotItem::Ball),
    kw("DISks", PlotItem::Disks),
    kw("BOU", PlotItem::Bou),
    kw("GRId", PlotItem::Grid),
    kw("CLUster", PlotItem::Cluster),
    kw("LCLuster", PlotItem::LCluster),
    kw("CND", PlotItem::Cnd),
    kw("LCNd", PlotItem::LCnd),
    kw("COUple", PlotItem::Couple),
    kw("FORces", PlotItem::Forces),
    kw("LFOrces", PlotItem::LForces),
    kw("MFOrces", PlotItem::MForces),
    kw("RDIsp", PlotItem::RDisp),
    kw("ROTation", PlotItem::Rotation),
    kw("SAVe", PlotItem::Save),
    kw("VELocity", PlotItem::Velocity),
    kw("WALL", PlotItem::Wall),
    kw("HIStory", PlotItem::History),
];

const PROBES: &[Keyword<ProbeKind>] = &[
    kw("E11", ProbeKind::E11),
    kw("E22", ProbeKind::E22),
    kw("E33", ProbeKind::E33),
    kw("E12", ProbeKind::E12),
    kw("E23", ProbeKind::E23),
    kw("E31", ProbeKind::E31),
    kw("E1M2", ProbeKind::E1m2),
    kw("E2M3", ProbeKind::E2m3),
    kw("E3M1", ProbeKind::E3m1),
];

const STRESS_SERVOS: &[Keyword<StressServo>] = &[
    kw("S0", StressServo::S0),
    kw("S1MS2", StressServo::S1ms2),
    kw("S11", StressServo::S11),
    kw("S22", StressServo::S22),
    kw("S33", StressServo::S33),
    kw("RING", StressServo::Ring),
];

#[derive(Clone, Copy)]
enum WallKw {
    P,
    Sp,
    Ob,
    Cy,
    V,
    M,
    Se,
}

const WALL_KWS: &[Keyword<WallKw>] = &[
    kw("P", WallKw::P),
    kw("SP", WallKw::Sp),
    kw("OB", WallKw::Ob),
    kw("CYlinder", WallKw::Cy),
    kw("V", WallKw::V),
    kw("M", WallKw::M),
    kw("SE", WallKw::Se),
];

#[derive(Clone, Copy)]
enum SetKw {
    Tol,
    Xres,
    Smin,
    Bridge,
    Tangential,
    Liquid,
    Periodic,
    Open,
    OutDir,
    View,
    Snapshot,
    History,
    GenOverlap,
    Fragment,
    Goldman,
    Tunnel,
    Normal,
    Rolling,
    Pair,
    Dashpot,
    WallBridges,
}

const SET_NAMES: &[Keyword<SetKw>] = &[
    kw("TOL", SetKw::Tol),
    kw("XRES", SetKw::Xres),
    kw("SMIN", SetKw::Smin),
    kw("BRIdge", SetKw::Bridge),
    kw("TANgential", SetKw::Tangential),
    kw("LIQuid", SetKw::Liquid),
    kw("PERiodic", SetKw::Periodic),
    kw("OPEn", SetKw::Open),
    kw("OUTdir", SetKw::OutDir),
    kw("VIEw", SetKw::View),
    kw("SNApshot", SetKw::Snapshot),
    kw("HIStory", SetKw::History),
    kw("GENoverlap", SetKw::GenOverlap),
    kw("FRAgment", SetKw::Fragment),
    kw("GOLdman", SetKw::Goldman),
    kw("TUNnel", SetKw::Tunnel),
    kw("NORmal", SetKw::Normal),
    kw("ROLling", SetKw::Rolling),
    kw("PAIr", SetKw::Pair),
    kw("DASHpot", SetKw::Dashpot),
    kw("WALlbridges", SetKw::WallBridges),
];

const DASHPOTS: &[Keyword<crate::sim::model::DashpotForm>] = &[
    kw("TRUBAL", crate::sim::model::DashpotForm::Exact),
    kw("LIGGGHTS", crate::sim::model::DashpotForm::Liggghts),
    kw("EDEM", crate::sim::model::DashpotForm::Liggghts),
    kw(
        "LIMITFORCE",
        crate::sim::model::DashpotForm::LiggghtsLimited,
    ),
];

const TUNNELS: &[Keyword<crate::sim::scene::TunnelAction>] = &[
    kw("STOP", crate::sim::scene::TunnelAction::Stop),
    kw("DELETE", crate::sim::scene::TunnelAction::Delete),
];

const BRIDGES: &[Keyword<BridgeChoice>] = &[
    kw("FIT", BridgeChoice::Fit),
    kw("TORoidal", BridgeChoice::Toroidal),
    kw("LAPlace", BridgeChoice::Laplace),
    kw("RABinovich", BridgeChoice::Rabinovich),
];
const TANGENTIALS: &[Keyword<TangentialChoice>] = &[
    kw("MD", TangentialChoice::Md),
    kw("NOSlip", TangentialChoice::NoSlip),
    kw("WALton", TangentialChoice::Walton),
    kw("HM", TangentialChoice::HertzMindlin),
    kw("MDR", TangentialChoice::Mdr),
];
const LIQUID_MODES: &[Keyword<LiquidMode>] = &[
    kw("LIAn", LiquidMode::Lian),
    kw("CONserve", LiquidMode::Conserve),
];
const VIEWS: &[Keyword<View>] = &[kw("XZ", View::Xz), kw("YZ", View::Yz), kw("XY", View::Xy)];
const AXES: &[Keyword<usize>] = &[kw("X", 0), kw("Y", 1), kw("Z", 2), kw("ALL", 3)];
const ONOFF: &[Keyword<bool>] = &[kw("ON", true), kw("OFF", false)];
const DEFAULT_KW: &[Keyword<()>] = &[kw("DEFault", ())];
/// The words of a range (`lang::range`), for the commands that take one.
const RANGE_KWS: &[&str] = &[
    "BOX", "SPHere", "CYLinder", "ID", "MATerial", "SIZe", "GROup", "NOT", "OR",
];

/// Every command, in alphabetical order of Appendix B plus trubal's additions.
pub const COMMANDS: &[CommandDef] = &[
    def!(
        "2-D",
        "",
        &[],
        true,
        |_| Ok(Command::TwoD),
        "Two-dimensional mode: particles move in the x-y plane only (z velocity and x,y spin held at zero); contact forces stay 3-D."
    ),
    def!(
        "AGGlomerate",
        "nagg xc yc zc RA",
        &[],
        true,
        b_agglomerate,
        "Define the spherical region of agglomerate nagg (1 or 2): centre (xc,yc,zc), radius RA. A generated particle is accepted only if it lies wholly inside (centre within RA - R)."
    ),
    def!(
        "AGEnerate",
        "isize imat iagg xo yo zo dx dy dz",
        &[],
        true,
        b_agenerate,
        "Regular (orthorhombic) lattice: sites (xo + i dx, yo + j dy, zo + k dz) inside the work-space, and inside agglomerate iagg's region if one is defined. Overlapping sites are skipped. BCC = two AGEnerate with offset origins. The sites are numbered layer by layer (z, then y, then x); an AGEnerate right after another into the same agglomerate (no command in between) numbers both lattices together in that order, so the ids of the first one's particles change (neighbours in space stay neighbours in memory, and two threads share few particles between their tasks). Only the sites in the region's bounding box are examined (in the work-space without a region); a lattice with more than 10^7 + 100 nball sites there (a step far below the particle size) is refused, as is one with more sites than the free places of nball. Ctrl-C stops it and places nothing. Needs the radius of isize only: the material mtyp may be defined after (Density re-computes the masses; the first Cycle asks for what is missing)."
    ),
    def!(
        "AWAll",
        "n [P a b c d | SP a b c d | OB a b c d | CYlinder x y z ax ay az r] [V vx vy vz [vr]] [M mtyp] [SE F vmax g]",
        &["P", "SP", "OB", "CYlinder", "V", "M", "SE"],
        true,
        b_awall,
        "Alter wall n: geometry (any kind to any other), velocity, material or servo (a V without SE takes a servo off: the wall then moves at V). Refused if the new geometry puts a particle's centre behind the wall's surface (with SET TUNnel STOP, the default)."
    ),
    def!(
        "BREak",
        "",
        &[],
        false,
        |a| b(a, ScriptCmd::Break),
        "Leave the innermost LOOP or WHILE now; the lines after it run (doc/language.md)."
    ),
    def!(
        "CALL",
        "name [arg ...]",
        &[],
        false,
        script::b_call,
        "Run the procedure name (DEFine) with the arguments (expressions, given to its parameters in order); RETurn ends it early. A procedure may call others, itself included, up to 64 deep."
    ),
    def!(
        "CGRavity",
        "nagg g",
        &[],
        false,
        b_cgravity,
        "Centripetal gravity of magnitude g (m/s^2) toward the centre of agglomerate nagg's region for its particles; g = 0 removes it (Lian ch. 7 preparation)."
    ),
    def!(
        "COHesion",
        "gamma mtyp",
        &[],
        true,
        b_cohesion,
        "Surface energy per surface gamma (J/m^2) of material mtyp: pull-off force Pc = 3 pi gamma R*. Papers quoting the work of adhesion mean Gamma = 2 gamma. Unlike materials use sqrt(gamma1 gamma2)."
    ),
    def!(
        "CReate",
        "x y z vx vy vz wx wy wz isize mtyp",
        &[],
        true,
        b_create,
        "Create one particle at (x,y,z) with velocity and angular velocity, size type and material type. Refused if it overlaps another particle. Needs the radius of isize only: the material mtyp may be defined after (Density re-computes the masses; the first Cycle asks for what is missing)."
    ),
    def!(
        "Cycle",
        "n [S0 v] [S1MS2 v] [S11 v] [S22 v] [S33 v] [RING v] [CALL name EVery k] [UNTIL cond]",
        &[
            "S0", "S1MS2", "S11", "S22", "S33", "RING", "CALL", "EVery", "UNTIL"
        ],
        true,
        b_cycle,
        "Run n time steps. Ctrl-C stops it at the end of the current step (the state is that of a shorter Cycle); on a terminal a run longer than 2 s shows a progress line. With stress-servo keywords the periodic cell's strain rates are adjusted every step to hold the named average stress (Pa, compression positive): S0 the mean (σ11+σ22+σ33)/3, S1MS2 the x-y mean, S11/S22/S33 one direction (GAIN and Mode first; doc/cell.md). A mean adjusts the axes whose GRID rate is 0. A Cycle with the same servo targets as the last one goes on with its servo (cycle 2000 S0 v runs as two cycle 1000 S0 v, across SAve/RESTart too) unless GRID, GAIN or Mode changed the cell in between. RING θ holds the angle of the major principal stress in the x-y plane (degrees from x towards y; ring shear) by turning the x-y strain-rate deviator (ed12 and ed11 - ed22). CALL name EVery k runs the procedure name (DEFine) at every cycle that is a multiple of k (a servo written by the user; it may change walls, velocities and variables, not cycle). UNTIL cond (the rest of the line) stops the Cycle after the first step at which the expression is true, n being the most (doc/language.md)."
    ),
    def!(
        "DAmping",
        "frac freq imass istiff iswitch | REStitution e [mtyp]",
        &["REStitution"],
        true,
        b_damping,
        "Rayleigh damping: fraction frac of critical at frequency freq (alpha = frac 2 pi freq on mass, beta = frac/(2 pi freq) on contact stiffness); imass/istiff = 1 switch the mass/contact part off; iswitch 1 = particle-particle, 0 = particle-wall. REStitution e: viscoelastic Hertz dashpot calibrated to give restitution e exactly."
    ),
    def!(
        "Density",
        "d mtyp",
        &[],
        true,
        b_density,
        "Mass density (kg/m^3) of material mtyp."
    ),
    def!(
        "DEFine",
        "name [param ...]",
        &[],
        false,
        script::b_define,
        "Define (or redefine) the procedure name: the lines up to the matching END are stored, not run; CALL name args runs them with the parameters set to the arguments (local to the call; every other variable is global). A procedure is part of the saved state (SAve). Example: `define push v` / `awall 1 v 0 0 -v` / `end`."
    ),
    def!(
        "DELete",
        "x1 x2 y1 y2 z1 z2 | range",
        RANGE_KWS,
        false,
        b_delete,
        "Delete the particles whose centres lie in the box x1<=x<=x2, y1<=y<=y2, z1<=z<=z2 (e.g. to cut a settled bed to a height), or the particles in a range (BOX, SPHere, CYLinder, ID, MATerial, SIZe, GROup, NOT, OR; doc/groups.md), with their contacts and bridges; what they held (kinetic energy, the strain energy of their contacts) leaves the energy ledger as work of commands. An error if no particle is in the box or range."
    ),
    def!(
        "DWAll",
        "P a b c d | SP a b c d | OB a b c d | CYlinder x y z ax ay az r [V vx vy vz [vr]] [M mtyp] [SE F vmax g]",
        &["P", "SP", "OB", "CYlinder", "V", "M", "SE"],
        true,
        b_dwall,
        "Define a wall: plane ax+by+cz=d (particles on the side the normal (a,b,c) points to), spherical container SP (centre a,b,c radius d, particles inside), obstacle/indenter OB (particles outside) or cylindrical die CYlinder (axis through (x,y,z) along (ax,ay,az), radius r, particles inside; infinitely long: close it with planes; Hertz R* = R sqrt(r/(r - R)), doc/indentation.md). V: velocity (and radial velocity vr for spheres and cylinders); M: material (default 1); SE: servo to normal/radial force F with max speed vmax and gain g. Refused if it puts a particle's centre behind its surface (outside a die, inside an indenter; with SET TUNnel STOP, the default); a warning names the particles it overlaps."
    ),
    def!(
        "ELSE",
        "",
        &[],
        false,
        |a| b(a, ScriptCmd::Else),
        "In an IF block: the lines up to END run when the IF's condition was false."
    ),
    def!(
        "END",
        "",
        &[],
        false,
        |a| b(a, ScriptCmd::End),
        "Closes the innermost IF, LOOP, WHILE or DEFine."
    ),
    def!(
        "FIEld",
        "n1 n2 n3 w [LUCy] | n1 n2 n3 BIN [IN x1 x2 y1 y2 z1 z2], then [FILe prefix] [CSV] [AVerage k m]",
        &["LUCy", "BIN", "IN", "FILe", "CSV", "AVerage"],
        false,
        b_field,
        "Coarse-grained continuum fields (Goldhirsch 2010, Weinhart et al. 2012) on n1 x n2 x n3 nodes over the work-space (node centres at (i + 1/2) L/n): density, velocity, contact and kinetic stress (Pa, compression positive, as PRint Stress), solid fraction and coordination, with a Gaussian kernel of standard deviation w (m, cut at 3w) or with LUCy Lucy's kernel of range w; w at least the node spacing. The kernel is normalised on the grid, so the mass on the grid is the particles' mass and the grid's mean contact stress the contact part of PRint Stress. Prints a summary (with --json every node); FILe also writes OUTdir/prefix_field_cNNNNNNNN.vti (VTK ImageData, doc/output.md), CSV OUTdir/prefix_field_cNNNNNNNN.csv (a line per node; prefix trubal without FILe). The velocity is the whole velocity (in a deforming cell the mean field G r added). AVerage k m: the time average of m states, this one and then one every k cycles during Cycle and RELax, printed and written when the m-th is taken (density, momentum, momentum flux and contact stress averaged, the velocity and kinetic stress made of the averages; Weinhart et al. 2012); a new AVerage replaces one still running. BIN (in the place of w): the box kernel, each node the average over its cell (the box of the node spacing around it), with the definitions of Window + PRint Stress (Pasha 2013 (5.1), Bagi): the particles whose centre lies in the cell, with all their contacts (walls included) at their contact points, over the cell's volume; IN x1 x2 y1 y2 z1 z2 puts the grid on that box instead of the work-space, so that the cells are bins of Pasha's (doc/indentation.md)."
    ),
    def!(
        "Fix",
        "ix iy iz irx iry irz iadd|All|range",
        &[
            "All", "BOX", "SPHere", "CYLinder", "ID", "MATerial", "SIZe", "GROup", "NOT", "OR"
        ],
        true,
        b_fix,
        "Hold velocity components constant (1 = fixed, 0 = free) for particle iadd, All, or the particles in a range now (e.g. GROup base; doc/groups.md). Does not zero them (see Zero). Over a dynamic group (GROup name alone) the Fix stands: before every step of a Cycle the particles then in the group are fixed and those that have left it are freed; all zeros ends it."
    ),
    def!(
        "FMM",
        "r",
        &[],
        true,
        |a| Ok(Command::Fmm { r: a.real("r")? }),
        "Multiply all applied particle forces by r."
    ),
    def!(
        "FRO",
        "",
        &[],
        true,
        |_| Ok(Command::Fro),
        "Set all angular velocities to zero."
    ),
    def!(
        "FRAction",
        "f | AUTO",
        &["AUTO"],
        true,
        |a| {
            const AUTO: &[Keyword<()>] = &[kw("AUTO", ())];
            Ok(Command::Fraction {
                f: if a.try_keyword(AUTO)?.is_some() {
                    None
                } else {
                    let t = a.peek();
                    let f = a.positive("f")?;
                    if f > MAX_FRACTION {
                        return Err(ParseError::at(
                            t.expect("positive() consumed a token"),
                            format!(
                                "FRAction {} is above {MAX_FRACTION}: accepted 0 < f <= {MAX_FRACTION} (0.2 is the default, 1 TRUBAL's; above about 1 most scenes blow up, doc/timestep.md)",
                                if f < 1e6 {
                                    format!("{f}")
                                } else {
                                    format!("{f:e}")
                                }
                            ),
                        ));
                    }
                    Some(f)
                },
            })
        },
        "Time step = f times the Rayleigh critical step pi Rmin sqrt(rho/G)/(0.1631 nu + 0.8766) (default 0.2; 0.1 with adhesion, and 0.1 in a scene that dissipates nothing: Hertz pairs without restitution, friction, adhesion, liquid or damping, whose energy then holds 1e-3 over 10^7 steps; times zeta(0.2)/zeta(e) when a pair's restitution e is below 0.1, e.g. 0.376 for e = 0.05, which PRint INFo says; at most 10). AUTO: at every rebuild of the candidate list the step is the smaller of that and 1/15 of the Hertz contact duration at the scene's largest approach speed (doc/timestep.md). Without AUTO a Cycle warns when its fastest contact gets fewer than 10 steps."
    ),
    def!(
        "FRiction",
        "amu mtyp",
        &[],
        true,
        b_friction,
        "Friction coefficient of material mtyp (particles and walls); a pair uses the smaller of the two."
    ),
    def!(
        "GAIN",
        "g edmax",
        &[],
        true,
        |a| Ok(Command::Gain {
            g: a.real("g")?,
            edmax: a.real("edmax")?
        }),
        "Gain g (1/(s Pa)) and largest strain rate edmax (1/s) of the periodic cell's stress servo (Cycle n S0 v ...; doc/cell.md)."
    ),
    def!(
        "GRAvity",
        "gx gy gz",
        &[],
        true,
        |a| Ok(Command::Gravity {
            g: a.vec3(["gx", "gy", "gz"])?
        }),
        "Uniform gravitational acceleration (m/s^2)."
    ),
    def!(
        "GRID",
        "ed11 ed22 ed33 ed12 ed23 ed31",
        &[],
        true,
        b_grid,
        "Strain rates of the periodic cell (1/s, ed_ij = dv_i/dx_j): ed11 ed22 ed33 stretch (> 0) or compress it, ed12 shears it with Lees-Edwards images (x step between the bottom and top y sides); ed23 and ed31 are not used (0). Particle velocities are then relative to the mean field (doc/cell.md)."
    ),
    def!(
        "GROup",
        "name [DYNamic] range | name FORget | name HIStory [OFF]",
        &[
            "DYNamic", "FORget", "HIStory", "OFF", "BOX", "SPHere", "CYLinder", "ID", "MATerial",
            "SIZe", "GROup", "NOT", "OR"
        ],
        false,
        b_group,
        "Name a range as a group (doc/groups.md). The range: conditions BOX x1 x2 y1 y2 z1 z2 (centre in the box), SPHere xc yc zc r, CYLinder x y z ax ay az r (centre within r of the axis; infinitely long), ID i [TO j] ..., MATerial m ..., SIZe s ..., GROup name; all must hold; NOT before a condition negates it; OR starts another set of conditions. A group is static: the particles in the range when GROup runs, by id (later moves do not change it; deleted particles leave it). DYNamic keeps the range instead: it is evaluated on the particles as they are whenever the group is used (a PRint, each history record, and before every step for a Fix standing on it). A group may be redefined; FORget removes it (refused while a dynamic group names it). HIStory: with every history record (SET HIStory n) the group's quantities (count, mass, x y z of the centre of mass, its velocity vx vy vz, kinetic, fx fy fz of the force sum, coordination; a dynamic group evaluated then) are recorded as columns NAME.QUANTITY of PRint HIStory; HIStory OFF stops that. Names: a letter then letters, digits, _ - . (at most 32, case-insensitive). In a periodic cell a BOX, SPHere or CYLinder wraps across the periodic sides (a centre is in it when one of its images in the neighbouring cells is). Groups are saved with SAve. Usable by Fix, DELete, VELocity, PROPerty, PRint GROup and PLot."
    ),
    def!(
        "HELP",
        "[command [item]]",
        &[],
        false,
        b_help,
        "List the commands, or describe one, or one of its items or keywords (help set outdir). The text is wrapped to the terminal's width (80 columns when not a terminal)."
    ),
    def!(
        "HIStory",
        "name EVery k expr | name OFF | WRIte file",
        &["EVery", "OFF", "WRIte"],
        false,
        script::b_history,
        "Record the value of any expression (the rest of the line; doc/language.md) at every cycle that is a multiple of k during cycling, next to the fixed columns of SET HIStory; a name given again starts it anew, OFF drops it. PRint HIStory prints each history as a table (cycle, time, value; with --json one object per history), PLot HIStory charts them against time (plot_cNNNNNNNN_histories.png in OUTdir), WRIte file writes them all to one CSV file (name, cycle, time, value). An expression that cannot be read at a record (a particle gone) records nothing there, with a warning. Histories and their rows are part of the saved state."
    ),
    def!(
        "IF",
        "cond",
        &[],
        false,
        script::b_if,
        "Run the lines up to ELSE (or END) when the expression cond (the rest of the line) is not 0, else the lines between ELSE and END. Example: `if ball_z(1) < 2*r` ... `else` ... `end`."
    ),
    def!(
        "Iset",
        "k iadd",
        &[],
        true,
        |a| {
            let _ = a.real("k")?;
            let _ = a.real("iadd")?;
            Ok(Command::Iset)
        },
        "Historical: poked raw memory. Use SET instead."
    ),
    def!(
        "INClude",
        "file",
        &[],
        false,
        script::b_include,
        "Run the lines of another command file here (a path relative to the working directory; with `/` in quotes). Its blocks must close in it; its errors stop it and name its lines. Included files may include others, 16 deep."
    ),
    def!(
        "LET",
        "name = expr",
        &[],
        false,
        script::b_let,
        "Set the variable name to the value of the expression (the rest of the line): numbers, + - * / % ^, comparisons (< <= > >= == !=, true = 1), and, or, not, the functions sqrt exp log log10 sin cos tan asin acos atan atan2 abs floor ceil round min max, the constant pi, and the queries of the scene: time, cycle, dt, nball, nwall; ball_x ball_y ball_z ball_vx ball_vy ball_vz ball_fx ball_fy ball_fz ball_r ball_m (id); wall_x wall_y wall_z (a plane's point nearest the origin, a sphere's or cylinder's centre), wall_d (a plane's d, a sphere's radius), wall_vx wall_vy wall_vz wall_fx wall_fy wall_fz wall_fn (n); sum(q) and avg(q) over all particles of q = x y z vx vy vz fx fy fz r m; and any number PRint shows, by its JSON name: energy.kinetic, info.contacts, stress.mean, stress.stress.3.3, bonds.damage_ratio, clusters.largest, chist.coordination, walls.walls.1.force.3 (the first word abbreviated as PRint's items; indices from 1). A variable holds a number (64-bit float); names are case-insensitive. Where a number goes in any command, a variable or an expression without blanks may stand (`rad 2*r0 1`), or any expression in square brackets (`rad [r0 / 2] 1`). `$name` is text: replaced before the line is read, by the --set value or else the variable's value (for file names: `save \"run_$i.sav\"`)."
    ),
    def!(
        "LIQuid",
        "pvol gsurf gcon gvis",
        &[],
        true,
        b_liquid,
        "Liquid bridges: volume pvol % of the mean volume of the two spheres, surface tension gsurf (N/m), contact angle gcon (degrees), viscosity gvis (Pa s). Bridges form on first solid contact and rupture at S_c. pvol = 0 removes all bridges."
    ),
    def!(
        "Log",
        "ON|OFF [file]",
        &["ON", "OFF"],
        true,
        b_log,
        "Echo commands and output to a log file (TRUBAL.OUT unless a file is named)."
    ),
    def!(
        "LOOP",
        "var from to [step]",
        &[],
        false,
        script::b_loop,
        "Run the lines up to END with the variable var = from, from + step, ... while not past to (step 1 unless given; not 0). The counter is the loop's own: setting var in the body does not change the count. At most 10^6 passes (a longer loop is refused before it starts)."
    ),
    def!(
        "Mode",
        "n",
        &[],
        true,
        |a| Ok(Command::Mode {
            n: a.int_in("n", 0, 1)?
        }),
        "Stress-servo mode: 0 velocity-increment control (each step the rate changes by -g × error), 1 velocity control (the rate is -g × error; does not hunt)."
    ),
    def!(
        "MOVe",
        "nagg dx dy dz",
        &[],
        false,
        |a| Ok(Command::Move {
            nagg: a.int_in("nagg", 1, 2)? as usize,
            d: a.vec3(["dx", "dy", "dz"])?,
        }),
        "Translate every particle of agglomerate nagg (and its region) by (dx, dy, dz); contacts with other particles are re-made at the next cycle."
    ),
    def!(
        "New",
        "",
        &[],
        true,
        |_| Ok(Command::New),
        "Forget the current problem; Start or Restart must follow."
    ),
    def!(
        "PLot",
        "item ...",
        &[
            "BALl", "DISks", "BOU", "GRId", "CLUster", "LCLuster", "CND", "LCNd", "COUple",
            "FORces", "LFOrces", "MFOrces", "RDIsp", "ROTation", "SAVe", "VELocity", "WALL",
            "HIStory"
        ],
        true,
        b_plot,
        "Write one PNG picture of the items (overlaid) to OUTdir as plot_cNNNNNNNN_items.png (doc/plots.md); the view is SET VIEw. SAVe stores the reference state for RDIsp, ROTation, CND/LCNd and the bond measures. HIStory (alone) charts what SET HIStory n recorded, with the columns of the groups recorded in it (GROup name HIStory: five panels a group). A range after the items (e.g. PLot BALl GROup top) draws the particles in it now in the highlight colour (with BALl, DISks, CLUster or LCLuster; the file name ends in _NAME, or _range; doc/groups.md)."
    ),
    def!(
        "PRA",
        "nu mtyp",
        &[],
        true,
        b_pra,
        "Poisson's ratio of material mtyp."
    ),
    def!(
        "PRint",
        "item ...",
        &[
            "Balls",
            "BONds",
            "CHist",
            "CLUsters",
            "Contacts",
            "All",
            "Gap",
            "ENErgy",
            "ENTries",
            "Grid",
            "HIStory",
            "Info",
            "Map",
            "Partitions",
            "SETtings",
            "Stress",
            "Walls",
            "GROup",
            "RANge"
        ],
        true,
        b_print,
        "Print the items (restricted by Window where it applies). GROup name (or ALL, every group) and RANge range: the sums and averages over a group's or a range's particles now (count, mass, centre of mass, its velocity, kinetic energy, force sum, mean coordination; doc/groups.md). Grid: the cell's rates, strains, image offset (in [-L_x/2, L_x/2): a small shear the negative way prints negative), servo gain and work. With --json each item is one JSON object per line."
    ),
    def!(
        "PRObe",
        "E11|E22|E33|E12|E23|E31|E1M2|E2M3|E3M1",
        &[
            "E11", "E22", "E33", "E12", "E23", "E31", "E1M2", "E2M3", "E3M1"
        ],
        true,
        |a| Ok(Command::Probe {
            kind: a.keyword(PROBES, "probe")?
        }),
        "Apply a strain probe to the periodic cell and print the modulus."
    ),
    def!(
        "PROPerty",
        "VELocity vx vy vz | SPIn wx wy wz | MATerial mtyp, then range",
        &[
            "VELocity", "SPIn", "MATerial", "BOX", "SPHere", "CYLinder", "ID", "SIZe", "GROup",
            "NOT", "OR"
        ],
        false,
        b_property,
        "Assign to the particles in a range now (doc/groups.md): VELocity (m/s), SPIn (angular velocity, rad/s) or MATerial (a defined material type; the masses follow its density, the contacts are re-evaluated at the next Cycle). The kinetic energy this adds or removes is booked as work of commands. An error if no particle is in the range."
    ),
    def!(
        "RAdius",
        "r isize [NORmal sd | UNIform rmin rmax | TABle r1 f1 r2 f2 ...]",
        &["NORmal", "UNIform", "TABle"],
        true,
        b_radius,
        "Radius (m) of size type isize. NORmal sd: generated particles draw radii from a normal distribution (mean r, standard deviation sd, truncated at 3 sd); UNIform rmin rmax: uniform in [rmin, rmax] (r is then the nominal radius); TABle r1 f1 r2 f2 ...: radius rk with number frequency fk (any unit: per cent or counts; they are normalised by their sum), e.g. Pasha 2013 Table 5.1 with its diameters halved. Existing particles of the type keep their radii unless the type is Fixed."
    ),
    def!(
        "RELax",
        "kmax fmax nmax",
        &[],
        false,
        |a| Ok(Command::Relax {
            kmax: a.non_negative("kmax")?,
            fmax: a.non_negative("fmax")?,
            nmax: a.count("nmax")? as u64,
        }),
        "Cycle until the kinetic energy is below kmax (J) and the largest net contact force below fmax (N) (solid + liquid bridge of a pair, Lian's criterion; checked every 100 cycles), or nmax cycles have run; prints which happened. Ctrl-C stops it like Cycle."
    ),
    def!(
        "RESEt",
        "",
        &[],
        true,
        |_| Ok(Command::Reset),
        "Set accumulated rotations to zero."
    ),
    def!(
        "RESTart",
        "[file]",
        &[],
        true,
        b_restart,
        "Load a saved state (default save.old). First command, or after New."
    ),
    def!(
        "RETurn",
        "[expr]",
        &[],
        false,
        script::b_return,
        "End the procedure being run; with an expression, its value is stored in the variable named after the procedure (`return h` in `define hard` sets `hard`)."
    ),
    def!(
        "RGEnerate",
        "n isize mtyp naggm [WAlls] | Seed n",
        &["Seed", "WAlls"],
        true,
        b_rgenerate,
        "Random generation of n particles in agglomerate region naggm (0 = whole work-space), rejecting overlaps; WAlls: also only where the whole particle lies on the particles' side of every wall (inside a die or container, above a floor, outside an indenter; the draws are confined to the walls' bounding box where a sphere, an axis-parallel cylinder or an axis-normal plane bounds it), without it a warning counts the particles placed behind walls; the placed particles are numbered along a space-filling (Morton) curve, so that neighbours in space are neighbours in memory; Seed n draws and discards n random numbers (TRUBAL's meaning: a placement takes three numbers, so seeds a few apart give nearly the same assembly shifted by a particle; for independent samples take seeds 10^7 apart, as scripts/ci_tables.py does). A target that random placement cannot reach is given up as soon as the rate of placement shows it (or the try limit of 1000 tries a particle is spent), keeping the particles that found room and saying so; Ctrl-C stops it and places nothing. Needs the radius of isize only: the material mtyp may be defined after (Density re-computes the masses; the first Cycle asks for what is missing)."
    ),
    def!(
        "RSet",
        "r iadd",
        &[],
        true,
        |a| {
            let _ = a.real("r")?;
            let _ = a.real("iadd")?;
            Ok(Command::Rset)
        },
        "Historical: poked raw memory. Use SET instead."
    ),
    def!(
        "SAve",
        "[file]",
        &[],
        true,
        b_save,
        "Save the whole state (default save.new)."
    ),
    def!(
        "SET",
        "name value",
        &[
            "TOL",
            "XRES",
            "SMIN",
            "BRIdge",
            "TANgential",
            "LIQuid",
            "PERiodic",
            "OPEn",
            "OUTdir",
            "VIEw",
            "SNApshot",
            "HIStory",
            "GENoverlap",
            "FRAgment",
            "GOLdman",
            "TUNnel",
            "NORmal",
            "ROLling",
            "PAIr",
            "DASHpot",
            "WALlbridges"
        ],
        false,
        b_set,
        "Settings: TOL d | XRES d | SMIN s (DEFault restores the automatic value; with TOL and XRES both automatic, a rebuild of the candidate list uses up to 2 x the automatic TOL when the fastest particle would otherwise force the next rebuild within 50 steps: fewer rebuilds, the same results to the bit; PRint ENTries shows the TOL of the list in use); BRIdge FIT|TOROIDAL|LAPLACE|RABINOVICH (RABINOVICH: Olsson 2017's wet model, Rabinovich force with the harmonic-mean radius capped at 2πRγcosθ in contact, 4πRγcosθ at a wall, Willett rupture distance, Nase viscous forces normal and tangential with S_min = R*/1000 unless SMIN is set; meant for Hertz contacts without COHesion, doc/bridge.md); TANgential MDR|MD|NOSLIP|WALTON|HM (MDR, the default: the exact Hertz-Mindlin contact by the method of dimensionality reduction (Popov & Hess 2015), a row of 16 springs per contact that keeps the traction field, within 5 % of the exact solution of oblique impacts from 5 deg where MD is not; pairs with COHesion or a law of SET NORmal keep MD; MD: Mindlin-Deresiewicz with Thornton's factors (Lian 1994), the force and its turning points; WALTON: Walton's incremental Mindlin–Deresiewicz law of Shang 1998; HM: the Hertz–Mindlin tangential law of EDEM and LIGGGHTS, the no-slip spring k_t = 8G*a with a dashpot from the pair's restitution, C_t = zeta (2/3 m* k_t)^(1/2), which the Mindlin springs of MJKR EDEM and NGUYEN pairs take too; doc/contact_laws.md); LIQuid LIAN|CONSERVE; PERiodic X|Y|Z|ALL; OPEn X|Y|Z|ALL; OUTdir path (the directory of PLot's pictures and PLot HIStory's charts; a path with `/` must be quoted, SET OUTdir \"runs/a\", as `/` separates words); VIEw XZ|YZ|XY; SNApshot n (blow-up snapshot interval); HIStory n (record every n cycles); GENoverlap f (overlap allowed between generated particles, fraction of Ri+Rj; default 1e-9); FRAgment eps (neighbour radius of Olsson's DBSCAN fragments in PRint CLUsters; DEFault 4 x mean radius); GOLdman ON|OFF (tangential viscous force of liquid bridges, Lian (4.76); OFF by default); TUNnel STOP|DELETE (a particle whose centre crossed a wall's surface stops the run with the last good state kept, the default, or is deleted with a warning and its energy booked as leaving); NORmal HERTZ | MJKR [EDEM [ROLLING]] | TNING py | PASHA ke kp kcp f0p [KT kt] | PFULL ke kp [KT kt] | NGUYEN, then [m1 [m2]] (the normal contact law of all material pairs, of the pairs with m1, or of the pair m1-m2; doc/contact_laws.md: HERTZ is Hertz, or JKR with COHesion, the default; MJKR the modified JKR of EDEM, broken at zero overlap, with EDEM the limit of sliding friction on the repulsive (Hertzian) part of the force, 4E*a^3/(3R*), instead of P + 2Pc (EDEM's Hertz-Mindlin with JKR; Mindlin's no-slip spring whatever SET TANgential says, with its dashpot under HM), with ROLLING the limit of the rolling moment too, instead of P; TNING Thornton-Ning's elastic-plastic adhesive law with limiting contact pressure py (Pa); PASHA Pasha's simplified linear elasto-plastic adhesive law with stiffnesses ke, kp (N/m), pull-off locus kcp (N/m) and f0p (N); PFULL his full model; KT the tangential stiffness of the linear laws, default ke; NGUYEN the JKR of Nguyen et al. (2014) as LIGGGHTS computes it, Olsson 2017's dry law: the JKR curve from the separation overlap alpha_s on, approaching as separating (no adhesion hysteresis), at a wall only at a positive overlap, with Mindlin's tangential spring capped at mu times the Hertz force instead of SET TANgential); ROLling mur [m1 [m2]] (rolling friction coefficient of the material pairs: a rolling spring on the relative rotation capped at mur Rr Fn, doc/contact_laws.md; 0 by default); PAIr m1 m2 [FRIction mu] [RESTitution e] | DEFault (the friction coefficient and the restitution of the pair of materials m1-m2, e.g. particles and a wall, instead of the smaller of the two materials' values; a value not given stays; DEFault returns the pair to that rule; e in (0, 1]); DASHpot TRUBAL|LIGGGHTS|EDEM|LIMITFORCE [m1 [m2]] (the form of the restitution dashpot of all material pairs, of the pairs with m1, or of the pair m1-m2, doc/contact_laws.md: TRUBAL, the default, calibrated so that a contact rebounds with e exactly and never pulls; LIGGGHTS and EDEM the formula of LIGGGHTS' hertz and EDEM's Hertz-Mindlin, -2 sqrt(5/6) beta sqrt(S_n m*) v_n with beta = ln e / sqrt(ln^2 e + pi^2) and S_n = 2E* sqrt(R* alpha), whose total force may pull at the end of a contact (LIGGGHTS' limitForce off); LIMITFORCE the same dashpot with the total force kept compressive (limitForce on), which rebounds livelier than e); WALlbridges ON|OFF (liquid bridges between particles and walls, ON by default: OFF, a wall contact is the dry contact of its law, as Lian 1994's smooth elastic wall with bridges only between particles; OFF removes the wall bridges there are)."
    ),
    def!(
        "SHow",
        "item ...",
        &[],
        false,
        script::b_show,
        "Print values and texts on one line: each item a \"quoted text\" or an expression (bare, or in [ ]). With --json one object {\"show\": [...]} of the values. Example: `show \"H =\" [h/1e6] \"MPa\"`."
    ),
    def!(
        "STArt",
        "xmax ymax zmax nbox nball nwall [Log]",
        &["Log"],
        true,
        b_start,
        "Define the work-space [0,xmax]x[0,ymax]x[0,zmax], the grid hint nbox, and capacities nball, nwall. Must come first."
    ),
    def!(
        "STOp",
        "",
        &[],
        true,
        |_| Ok(Command::Stop),
        "End the session (the state is not saved); `quit` and `exit` do the same."
    ),
    def!(
        "VELocity",
        "v1x v1y v1z [v2x v2y v2z] ivd | vx vy vz range",
        RANGE_KWS,
        true,
        b_velocity,
        "Set the velocity of every particle of agglomerate 1 (and 2); ivd = 1 marks the impact: contacts made afterwards use the base surface energy. With three numbers and a range (e.g. VELocity 0 0 -1 GROup top), the velocity of the particles in the range now (as PROPerty VELocity; doc/groups.md)."
    ),
    def!(
        "VMU",
        "r",
        &[],
        true,
        |a| Ok(Command::Vmu { r: a.real("r")? }),
        "Multiply the velocities of fixed degrees of freedom by r."
    ),
    def!(
        "VTk",
        "[EVery k] [FILe prefix] [RAW] [SINgle] [ARRays name ...] [CONtacts name ...] | OFF",
        &[
            "EVery", "FILe", "RAW", "SINgle", "ARRays", "CONtacts", "OFF"
        ],
        false,
        b_vtk,
        "Write a VTK frame for ParaView now: four XML PolyData files in OUTdir, prefix_particles_cNNNNNNNN.vtp (points with id, radius, velocity, spin, force, moment, material, size type, agglomerate, coordination, cluster, and displacement since PLot SAve), prefix_contacts_... (lines between centres with the forces, overlap and bridge), prefix_walls_... (surfaces with their forces), prefix_cell_... (the work-space box), binary (appended, zlib-compressed; RAW: uncompressed, for this command's frames and its schedule's). ARRays names the particle arrays written, as LIGGGHTS' dump custom picks columns (id radius velocity spin force moment material size_type agglomerate coordination cluster displacement; the positions always; all without ARRays), for this command's frames and its schedule's: ARRays id radius velocity makes the particles file about half the size (38.2 bytes a particle against 72.4 on the settled S1 bed, doc/output.md). CONtacts names the contact file's arrays the same way (a b wall force normal_force_vector tangential_force_vector normal_force tangential_force overlap contact_radius bridge_volume bridge; the lines always; all without CONtacts): CONtacts normal_force makes it 44.0 bytes a particle against 156.8. SINgle writes the points (centres, line ends, wall vertices) in single precision, as the arrays are: a relative precision of 6e-8 of the coordinate, below a micrometre in a metre-sized work-space, enough to look at but not to recompute overlaps from; with ARRays id radius velocity CONtacts normal_force the frame is 57 bytes a particle (82 without SINgle). Also a series index prefix_KIND.pvd for each kind that ParaView opens as a time series (doc/output.md). EVery k: also every k cycles during Cycle and RELax (at the cycles that are multiples of k); OFF stops that. The prefix is trubal unless FILe names one (letters, digits, `_`, `-`, `.`). The series goes on across sessions: the first frame of a prefix keeps the frames an existing prefix_particles.pvd in OUTdir lists before the current cycle (after RESTart from a SAve the series continues; frames at later cycles, of a run the restart abandoned, leave the index)."
    ),
    def!(
        "WHILE",
        "cond",
        &[],
        false,
        script::b_while,
        "Run the lines up to END again and again while the expression cond (the rest of the line) is not 0, at most 10^6 passes (more is a runaway loop: an error). Ctrl-C stops any loop."
    ),
    def!(
        "Window",
        "x1 x2 y1 y2 z1 z2",
        &[],
        true,
        b_window,
        "Restrict printing to x1<=x<=x2, y1<=y<=y2, z1<=z<=z2."
    ),
    def!(
        "YMD",
        "ymod mtyp",
        &[],
        true,
        b_ymd,
        "Young's modulus (Pa) of material mtyp."
    ),
    def!(
        "Zero",
        "izf",
        &[],
        true,
        |a| Ok(Command::Zero {
            always: a.flag("izf")?
        }),
        "Zero all velocities; izf = 1 also after every cycle, 0 cancels."
    ),
];

/// The command keywords, in table order (for matching and completion).
/// Words that name a command outside the abbreviation rule: Appendix B.1's own example
/// gives `p c` for `PRint Contacts`, although `p` is also the start of `PLot`.
/// `quit` and `exit` end the session as STOp does.
pub const ALIASES: &[(&str, &str)] = &[("P", "PRint"), ("QUIT", "STOp"), ("EXIT", "STOp")];

/// The command an alias names.
pub fn alias(word: &str) -> Option<usize> {
    let (_, name) = ALIASES.iter().find(|(a, _)| a.eq_ignore_ascii_case(word))?;
    COMMANDS.iter().position(|d| d.name == *name)
}

/// The command a word names: an alias, or by the abbreviation rule.
pub fn find_command(
    word: &str,
    keys: &[Keyword<usize>],
) -> Result<usize, super::keyword::MatchError> {
    match alias(word) {
        Some(i) => Ok(i),
        None => super::keyword::match_keyword(word, keys),
    }
}

/// The command words as keywords (their index in [`COMMANDS`]), built once.
pub fn command_keywords() -> &'static [Keyword<usize>] {
    static KEYS: std::sync::LazyLock<Vec<Keyword<usize>>> = std::sync::LazyLock::new(|| {
        COMMANDS
            .iter()
            .enumerate()
            .map(|(i, d)| kw(d.name, i))
            .collect()
    });
    &KEYS
}

/// A script word without parameters.
fn b(_: &mut Args, c: ScriptCmd) -> Result<Command, ParseError> {
    Ok(Command::Script(c))
}

fn material(a: &mut Args) -> Result<usize, ParseError> {
    a.material_type("mtyp")
}

fn b_agglomerate(a: &mut Args) -> Result<Command, ParseError> {
    Ok(Command::Agglomerate {
        nagg: a.int_in("nagg", 1, 2)? as usize,
        centre: a.vec3(["xc", "yc", "zc"])?,
        radius: a.positive("RA")?,
    })
}

fn b_agenerate(a: &mut Args) -> Result<Command, ParseError> {
    let size = a.size_type("isize")?;
    let material = material(a)?;
    let nagg = a.int_in("iagg", 0, 2)? as usize;
    let origin = a.vec3(["xo", "yo", "zo"])?;
    let step = [a.positive("dx")?, a.positive("dy")?, a.positive("dz")?];
    Ok(Command::Agenerate {
        size,
        material,
        nagg,
        origin,
        step,
    })
}

fn wall_options(a: &mut Args, opts: &mut WallOptions) -> Result<(), ParseError> {
    while let Some(k) = a.try_keyword(WALL_KWS)? {
        match k {
            WallKw::P => {
                let n = a.vec3(["a", "b", "c"])?;
                let d = a.real("d")?;
                opts.geom = Some(WallGeom::Plane { normal: n, d });
            }
            WallKw::Sp | WallKw::Ob => {
                let c = a.vec3(["a", "b", "c"])?;
                let r = a.positive("d (radius)")?;
                opts.geom = Some(if matches!(k, WallKw::Sp) {
                    WallGeom::Sphere {
                        centre: c,
                        radius: r,
                    }
                } else {
                    WallGeom::Obstacle {
                        centre: c,
                        radius: r,
                    }
                });
            }
            WallKw::Cy => {
                let point = a.vec3(["x", "y", "z"])?;
                let t = a.peek();
                let axis = a.vec3(["ax", "ay", "az"])?;
                if axis.iter().all(|&x| x == 0.0) {
                    return Err(ParseError::at(
                        t.expect("consumed"),
                        "a cylinder needs a non-zero axis (ax, ay, az)",
                    ));
                }
                let radius = a.positive("r (radius)")?;
                opts.geom = Some(WallGeom::Cylinder {
                    point,
                    axis,
                    radius,
                });
            }
            WallKw::V => {
                let v = a.vec3(["vx", "vy", "vz"])?;
                let vr = if a.peek_is_number() {
                    a.real("vr")?
                } else {
                    0.0
                };
                opts.vel = Some((v, vr));
            }
            WallKw::M => opts.material = Some(material(a)?),
            WallKw::Se => {
                opts.servo = Some(Servo {
                    force: a.real("F")?,
                    vmax: a.non_negative("vmax")?,
                    gain: a.non_negative("g")?,
                })
            }
        }
    }
    Ok(())
}

fn b_dwall(a: &mut Args) -> Result<Command, ParseError> {
    let first = a.peek();
    let mut opts = WallOptions::default();
    wall_options(a, &mut opts)?;
    if opts.geom.is_none() {
        return Err(match first {
            Some(t) => ParseError::at(
                t,
                "DWAll needs the geometry first: P a b c d, SP a b c d, OB a b c d or CYlinder x y z ax ay az r",
            ),
            None => ParseError {
                start: a.line_end,
                end: a.line_end + 1,
                message: "DWAll needs a geometry: P a b c d, SP a b c d, OB a b c d or CYlinder x y z ax ay az r".into(),
            },
        });
    }
    Ok(Command::Dwall(opts))
}

fn b_awall(a: &mut Args) -> Result<Command, ParseError> {
    let n = a.index("n")?;
    let mut opts = WallOptions::default();
    wall_options(a, &mut opts)?;
    Ok(Command::Awall { n, opts })
}

fn b_cgravity(a: &mut Args) -> Result<Command, ParseError> {
    Ok(Command::Cgravity {
        nagg: a.int_in("nagg", 1, 2)? as usize,
        g: a.non_negative("g")?,
    })
}

fn b_cohesion(a: &mut Args) -> Result<Command, ParseError> {
    let gamma = a.non_negative("gamma")?;
    let material = material(a)?;
    let base = if a.peek_is_number() {
        Some(a.non_negative("gamma_base")?)
    } else {
        None
    };
    Ok(Command::Cohesion {
        gamma,
        material,
        base,
    })
}

fn b_create(a: &mut Args) -> Result<Command, ParseError> {
    Ok(Command::Create {
        pos: a.vec3(["x", "y", "z"])?,
        vel: a.vec3(["vx", "vy", "vz"])?,
        spin: a.vec3(["wx", "wy", "wz"])?,
        size: a.size_type("isize")?,
        material: material(a)?,
    })
}

fn b_cycle(a: &mut Args) -> Result<Command, ParseError> {
    let n = a.int_in("n", 0, i64::MAX / 2)? as u64;
    let mut servo = Vec::new();
    while let Some(k) = a.try_keyword(STRESS_SERVOS)? {
        servo.push((k, a.real("v")?));
    }
    if let Some(c) = super::script::cycle_options(a, n, &servo)? {
        return Ok(c);
    }
    Ok(Command::Cycle { n, servo })
}

fn b_damping(a: &mut Args) -> Result<Command, ParseError> {
    const RES: &[Keyword<()>] = &[kw("REStitution", ())];
    if a.try_keyword(RES)?.is_some() {
        let t = a.peek();
        let e = a.real("e")?;
        if !(e > 0.0 && e <= 1.0) {
            return Err(ParseError::at(
                t.expect("consumed"),
                format!("restitution e must be in (0, 1], got {e}"),
            ));
        }
        let material = if a.peek_is_number() {
            Some(material(a)?)
        } else {
            None
        };
        return Ok(Command::Damping(DampingSpec::Restitution { e, material }));
    }
    Ok(Command::Damping(DampingSpec::Rayleigh {
        frac: a.non_negative("frac")?,
        freq: a.positive("freq")?,
        mass_off: a.flag("imass")?,
        stiff_off: a.flag("istiff")?,
        ball_ball: a.flag("iswitch")?,
    }))
}

fn b_density(a: &mut Args) -> Result<Command, ParseError> {
    Ok(Command::Density {
        rho: a.positive("d")?,
        material: material(a)?,
    })
}

fn b_fix(a: &mut Args) -> Result<Command, ParseError> {
    let mut flags = [false; 6];
    for (f, n) in flags
        .iter_mut()
        .zip(["ix", "iy", "iz", "irx", "iry", "irz"])
    {
        *f = a.flag(n)?;
    }
    const ALL: &[Keyword<()>] = &[kw("All", ())];
    let target = if a.try_keyword(ALL)?.is_some() {
        FixTarget::All
    } else if super::range::starts_range(a) {
        FixTarget::Range(super::range::range(a)?)
    } else {
        FixTarget::Particle(a.index("iadd")?)
    };
    Ok(Command::Fix { flags, target })
}

fn b_friction(a: &mut Args) -> Result<Command, ParseError> {
    Ok(Command::Friction {
        mu: a.non_negative("amu")?,
        material: material(a)?,
    })
}

fn b_grid(a: &mut Args) -> Result<Command, ParseError> {
    let mut rates = [0.0; 6];
    for (r, n) in rates
        .iter_mut()
        .zip(["ed11", "ed22", "ed33", "ed12", "ed23", "ed31"])
    {
        *r = a.real(n)?;
    }
    Ok(Command::Grid { rates })
}

fn b_help(a: &mut Args) -> Result<Command, ParseError> {
    let topic = if a.at_end() {
        None
    } else {
        Some(a.word("command")?)
    };
    let item = if a.at_end() {
        None
    } else {
        Some(a.word("item")?)
    };
    Ok(Command::Help { topic, item })
}

fn b_liquid(a: &mut Args) -> Result<Command, ParseError> {
    let pvol = a.non_negative("pvol")?;
    let t = a.peek();
    let gsurf = a.non_negative("gsurf")?;
    if pvol > 0.0 && gsurf <= 0.0 {
        return Err(ParseError::at(
            t.expect("consumed"),
            "gsurf (surface tension) must be positive when pvol > 0",
        ));
    }
    let t = a.peek();
    let theta_deg = a.real("gcon")?;
    if !(0.0..90.0).contains(&theta_deg) {
        return Err(ParseError::at(
            t.expect("consumed"),
            format!("contact angle gcon must be in [0, 90) degrees, got {theta_deg}"),
        ));
    }
    let eta = a.non_negative("gvis")?;
    Ok(Command::Liquid {
        pvol,
        gsurf,
        theta_deg,
        eta,
    })
}

fn b_log(a: &mut Args) -> Result<Command, ParseError> {
    let on = a.keyword(ONOFF, "ON or OFF")?;
    let file = if a.at_end() {
        None
    } else {
        Some(a.word("file")?)
    };
    Ok(Command::Log { on, file })
}

fn b_plot(a: &mut Args) -> Result<Command, ParseError> {
    let mut items = Vec::new();
    while let Some(k) = a.try_keyword(PLOT_ITEMS)? {
        items.push(k);
    }
    if items.is_empty() {
        let msg = "PLot needs at least one item";
        return Err(match a.peek() {
            Some(t) => ParseError::at(
                t,
                format!(
                    "{msg}: {}",
                    super::keyword::match_keyword(&t.text, PLOT_ITEMS)
                        .err()
                        .map(|e| e.describe(&t.text, "plot item", PLOT_ITEMS))
                        .unwrap_or_default()
                ),
            ),
            None => ParseError {
                start: a.line_end,
                end: a.line_end + 1,
                message: format!("{msg} (BALl, FORces, CND, SAVe, ...)"),
            },
        });
    }
    let mark = if super::range::starts_range(a) {
        Some(super::range::range(a)?)
    } else {
        None
    };
    Ok(Command::Plot { items, mark })
}

const FIELD_WORDS: &[Keyword<u8>] = &[
    kw("LUCy", 0),
    kw("FILe", 1),
    kw("CSV", 2),
    kw("AVerage", 3),
    kw("IN", 4),
];

fn b_field(a: &mut Args) -> Result<Command, ParseError> {
    let nodes = [
        a.int_in("n1", 1, 1 << 24)? as usize,
        a.int_in("n2", 1, 1 << 24)? as usize,
        a.int_in("n3", 1, 1 << 24)? as usize,
    ];
    // `BIN` in the place of the width: the box kernel.
    let bin = a.try_keyword(&[kw("BIN", ())])?.is_some();
    let width = if bin { 0.0 } else { a.positive("w")? };
    let (mut lucy, mut prefix, mut csv, mut average) = (false, None, false, None);
    let mut region = None;
    while let Some(t) = a.peek() {
        let Some(k) = a.try_keyword(FIELD_WORDS)? else {
            break;
        };
        let again = match k {
            0 if bin => {
                return Err(ParseError::at(
                    t,
                    "FIEld: LUCy is a smooth kernel; BIN is the box kernel: one of the two",
                ));
            }
            0 => std::mem::replace(&mut lucy, true),
            1 => prefix.replace(vtk_prefix(a)?).is_some(),
            2 => std::mem::replace(&mut csv, true),
            3 => {
                let every = a.int_in("k", 1, i64::MAX / 2)? as u64;
                let samples = a.int_in("m", 1, 1 << 32)? as u64;
                average.replace((every, samples)).is_some()
            }
            _ if !bin => {
                return Err(ParseError::at(
                    t,
                    "FIEld: IN takes the box kernel only (FIEld n1 n2 n3 BIN IN x1 x2 y1 y2 z1 z2): a smooth kernel's grid is the work-space",
                ));
            }
            _ => {
                let b = box_bounds(a, true)?;
                if b[1] <= b[0] || b[3] <= b[2] || b[5] <= b[4] {
                    return Err(ParseError::at(
                        t,
                        "FIEld IN: the box must have a positive size on every axis",
                    ));
                }
                region.replace(b).is_some()
            }
        };
        if again {
            return Err(ParseError::at(
                t,
                format!("FIEld: `{}` given twice", t.text),
            ));
        }
    }
    Ok(Command::Field {
        nodes,
        width,
        lucy,
        prefix,
        csv,
        average,
        bin,
        region,
    })
}

/// The series prefix after `FILe` (VTk, FIEld): a plain file-name part.
fn vtk_prefix(a: &mut Args) -> Result<String, ParseError> {
    let w = a.peek();
    let name = a.word("prefix")?;
    let ok = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "_-.".contains(c));
    if !ok {
        return Err(ParseError::at(
            w.expect("word() consumed a token"),
            format!(
                "FILe: the prefix `{name}` may hold letters, digits, `_`, `-` and `.` only (the directory is SET OUTdir)"
            ),
        ));
    }
    Ok(name)
}

const VTK_WORDS: &[Keyword<u8>] = &[
    kw("EVery", 0),
    kw("FILe", 1),
    kw("OFF", 2),
    kw("RAW", 3),
    kw("ARRays", 4),
    kw("CONtacts", 5),
    kw("SINgle", 6),
];

/// The names `VTk ARRays` takes, index into [`PARTICLE_ARRAYS`].
const ARRAY_WORDS: &[Keyword<u8>] = &[
    kw("ID", 0),
    kw("RADius", 1),
    kw("VELocity", 2),
    kw("SPIn", 3),
    kw("FORce", 4),
    kw("MOMent", 5),
    kw("MATerial", 6),
    kw("SIZe_type", 7),
    kw("AGGlomerate", 8),
    kw("COOrdination", 9),
    kw("CLUster", 10),
    kw("DISplacement", 11),
];

/// The names `VTk CONtacts` takes, index into [`CONTACT_ARRAYS`].
const CONTACT_WORDS: &[Keyword<u8>] = &[
    kw("A", 0),
    kw("B", 1),
    kw("WALl", 2),
    kw("FORce", 3),
    kw("NORMAL_FORCE_Vector", 4),
    kw("TANGENTIAL_FORCE_Vector", 5),
    kw("NORmal_force", 6),
    kw("TANgential_force", 7),
    kw("OVErlap", 8),
    kw("CONTACT_Radius", 9),
    kw("BRIDGE_Volume", 10),
    kw("BRIdge", 11),
];

/// The array names after `ARRays` (`CONtacts`), up to the next `VTk` keyword or the end
/// (at least one; each once): a bit per entry of `all` ([`PARTICLE_ARRAYS`] or
/// [`CONTACT_ARRAYS`]), whose words are `words`.
fn vtk_arrays(
    a: &mut Args,
    after: &Token,
    words: &[Keyword<u8>],
    all: &[&str],
) -> Result<u16, ParseError> {
    let (word, what, always) = if all == PARTICLE_ARRAYS {
        (
            "ARRays",
            "particle array",
            "the positions are always written",
        )
    } else {
        ("CONtacts", "contact array", "the lines are always written")
    };
    let mut set = 0u16;
    while let Some(t) = a.peek() {
        if super::keyword::match_keyword(&t.text, VTK_WORDS).is_ok() {
            break;
        }
        let k = a.keyword(words, what)?;
        if set & (1 << k) != 0 {
            return Err(ParseError::at(
                t,
                format!("VTk {word}: `{}` given twice", t.text),
            ));
        }
        set |= 1 << k;
    }
    if set == 0 {
        return Err(ParseError::at(
            after,
            format!(
                "VTk {word}: name the {what}s to write ({}; {always})",
                all.join(", ")
            ),
        ));
    }
    Ok(set)
}

fn b_vtk(a: &mut Args) -> Result<Command, ParseError> {
    let (mut every, mut off, mut prefix) = (None, false, None);
    let mut layout = VtkLayout::default();
    while let Some(t) = a.peek() {
        let Some(k) = a.try_keyword(VTK_WORDS)? else {
            break;
        };
        let again = match k {
            0 => every
                .replace(a.int_in("k", 1, i64::MAX / 2)? as u64)
                .is_some(),
            1 => prefix.replace(vtk_prefix(a)?).is_some(),
            2 => std::mem::replace(&mut off, true),
            3 => std::mem::replace(&mut layout.raw, true),
            4 => layout
                .arrays
                .replace(vtk_arrays(a, t, ARRAY_WORDS, &PARTICLE_ARRAYS)?)
                .is_some(),
            5 => layout
                .contacts
                .replace(vtk_arrays(a, t, CONTACT_WORDS, &CONTACT_ARRAYS)?)
                .is_some(),
            _ => std::mem::replace(&mut layout.single, true),
        };
        if again {
            return Err(ParseError::at(t, format!("VTk: `{}` given twice", t.text)));
        }
    }
    if off && (every.is_some() || prefix.is_some() || layout != VtkLayout::default()) {
        return Err(ParseError {
            start: a.line_end,
            end: a.line_end + 1,
            message: "VTk OFF stands alone (it stops the schedule of EVery)".into(),
        });
    }
    Ok(Command::Vtk {
        every,
        off,
        prefix,
        layout,
    })
}

fn b_pra(a: &mut Args) -> Result<Command, ParseError> {
    let t = a.peek();
    let nu = a.real("nu")?;
    if !(-1.0 < nu && nu < 0.5) {
        return Err(ParseError::at(
            t.expect("consumed"),
            format!("Poisson's ratio must be in (-1, 0.5), got {nu}"),
        ));
    }
    Ok(Command::Pra {
        nu,
        material: material(a)?,
    })
}

fn b_print(a: &mut Args) -> Result<Command, ParseError> {
    let mut items = Vec::new();
    let mut ranges = Vec::new();
    while let Some(t) = a.peek()
        && let Some(k) = a.try_keyword(PRINT_ITEMS)?
    {
        let k = match k {
            PrintItem::Contacts(_) => match a.try_keyword(CONTACT_FILTERS)? {
                Some(f) => PrintItem::Contacts(f),
                None => k,
            },
            PrintItem::Range => {
                ranges.push(print_range(a, t)?);
                k
            }
            _ => k,
        };
        items.push(k);
    }
    if items.is_empty() {
        return Err(match a.peek() {
            Some(t) => ParseError::at(
                t,
                super::keyword::match_keyword(&t.text, PRINT_ITEMS)
                    .err()
                    .map(|e| e.describe(&t.text, "print item", PRINT_ITEMS))
                    .unwrap_or_default(),
            ),
            None => ParseError {
                start: a.line_end,
                end: a.line_end + 1,
                message: "PRint needs at least one item (Balls, Contacts, Energy, Info, ...)"
                    .into(),
            },
        });
    }
    Ok(Command::Print { items, ranges })
}

/// The range of `PRint GROup name|ALL` (`None`: every group) or `PRint RANge range`; `t` the
/// item's word.
fn print_range(a: &mut Args, t: &super::lexer::Token) -> Result<Option<Range>, ParseError> {
    const WHICH: &[Keyword<bool>] = &[kw("GROup", true), kw("RANge", false)];
    const ALL: &[Keyword<()>] = &[kw("ALL", ())];
    if super::keyword::match_keyword(&t.text, WHICH) == Ok(false) {
        return super::range::range(a).map(Some);
    }
    if a.try_keyword(ALL)?.is_some() {
        return Ok(None);
    }
    Ok(Some(Range::group(&super::range::group_name(a)?)))
}

fn b_group(a: &mut Args) -> Result<Command, ParseError> {
    #[derive(Clone, Copy, PartialEq)]
    enum W {
        Dynamic,
        Forget,
        History,
    }
    const WORDS: &[Keyword<W>] = &[
        kw("DYNamic", W::Dynamic),
        kw("FORget", W::Forget),
        kw("HIStory", W::History),
    ];
    const OFF: &[Keyword<()>] = &[kw("OFF", ())];
    let name = super::range::group_name(a)?;
    let action = match a.try_keyword(WORDS)? {
        Some(W::Forget) => GroupAction::Forget,
        Some(W::History) => GroupAction::Record(a.try_keyword(OFF)?.is_none()),
        Some(W::Dynamic) => GroupAction::Define {
            range: super::range::range(a)?,
            dynamic: true,
        },
        None => GroupAction::Define {
            range: super::range::range(a)?,
            dynamic: false,
        },
    };
    Ok(Command::Group { name, action })
}

fn b_property(a: &mut Args) -> Result<Command, ParseError> {
    #[derive(Clone, Copy)]
    enum W {
        Velocity,
        Spin,
        Material,
    }
    const WORDS: &[Keyword<W>] = &[
        kw("VELocity", W::Velocity),
        kw("SPIn", W::Spin),
        kw("MATerial", W::Material),
    ];
    let what = match a.keyword(WORDS, "property (VELocity, SPIn or MATerial)")? {
        W::Velocity => Property::Velocity(a.vec3(["vx", "vy", "vz"])?),
        W::Spin => Property::Spin(a.vec3(["wx", "wy", "wz"])?),
        W::Material => Property::Material(a.material_type("mtyp")?),
    };
    Ok(Command::Property {
        what,
        range: super::range::range(a)?,
    })
}

fn b_radius(a: &mut Args) -> Result<Command, ParseError> {
    #[derive(Clone, Copy)]
    enum D {
        N,
        U,
        T,
    }
    const DISTS: &[Keyword<D>] = &[kw("NORmal", D::N), kw("UNIform", D::U), kw("TABle", D::T)];
    let r = a.positive("r")?;
    let size = a.size_type("isize")?;
    let dist = match a.try_keyword(DISTS)? {
        None => SizeDist::Fixed,
        Some(D::N) => {
            let t = a.peek();
            let sd = a.positive("sd")?;
            if 3.0 * sd >= r {
                return Err(ParseError::at(
                    t.expect("consumed"),
                    format!("sd = {sd} is too large: r - 3 sd must stay positive"),
                ));
            }
            SizeDist::Normal { sd }
        }
        Some(D::U) => {
            let min = a.positive("rmin")?;
            let t = a.peek();
            let max = a.positive("rmax")?;
            if max < min {
                return Err(ParseError::at(
                    t.expect("consumed"),
                    "rmax must not be below rmin",
                ));
            }
            SizeDist::Uniform { min, max }
        }
        Some(D::T) => {
            let (mut radius, mut freq) = (Vec::new(), Vec::new());
            while a.peek_is_number() {
                radius.push(a.positive("rk")?);
                freq.push(a.non_negative("fk")?);
            }
            if radius.is_empty() {
                return Err(match a.peek() {
                    Some(t) => ParseError::at(t, "TABle needs pairs of numbers: r1 f1 r2 f2 ..."),
                    None => ParseError {
                        start: a.line_end,
                        end: a.line_end + 1,
                        message: "TABle needs pairs of numbers: r1 f1 r2 f2 ...".into(),
                    },
                });
            }
            if !freq.iter().any(|&f| f > 0.0) || !freq.iter().sum::<f64>().is_finite() {
                return Err(ParseError {
                    start: a.line_end,
                    end: a.line_end + 1,
                    message: "the frequencies of TABle must be finite with at least one above 0"
                        .into(),
                });
            }
            SizeDist::Table { radius, freq }
        }
    };
    Ok(Command::Radius { r, size, dist })
}

fn optional_file(a: &mut Args) -> Result<Option<String>, ParseError> {
    Ok(if a.at_end() {
        None
    } else {
        Some(a.word("file")?)
    })
}

fn b_restart(a: &mut Args) -> Result<Command, ParseError> {
    Ok(Command::Restart {
        file: optional_file(a)?,
    })
}

fn b_save(a: &mut Args) -> Result<Command, ParseError> {
    Ok(Command::Save {
        file: optional_file(a)?,
    })
}

fn b_rgenerate(a: &mut Args) -> Result<Command, ParseError> {
    const SEED: &[Keyword<()>] = &[kw("Seed", ())];
    if a.try_keyword(SEED)?.is_some() {
        return Ok(Command::RgenerateSeed {
            n: a.count("n")? as u64,
        });
    }
    Ok(Command::Rgenerate {
        n: a.count("n")?,
        size: a.size_type("isize")?,
        material: material(a)?,
        nagg: a.int_in("naggm", 0, 2)? as usize,
        walls: {
            const WALLS: &[Keyword<()>] = &[kw("WAlls", ())];
            a.try_keyword(WALLS)?.is_some()
        },
    })
}

fn length_or_default(a: &mut Args, name: &str) -> Result<Option<f64>, ParseError> {
    if a.try_keyword(DEFAULT_KW)?.is_some() {
        Ok(None)
    } else {
        Ok(Some(a.positive(name)?))
    }
}

/// `SET NORmal law [parameters] [KT kt] [m1 [m2]]`.
fn normal_law(a: &mut Args) -> Result<Setting, ParseError> {
    const LAWS: &[Keyword<u8>] = &[
        kw("HERtz", 0),
        kw("JKR", 0),
        kw("MJKr", 1),
        kw("TNIng", 2),
        kw("PASha", 3),
        kw("PFUll", 4),
        kw("NGUyen", 5),
    ];
    const KT: &[Keyword<()>] = &[kw("KT", ())];
    let stiffnesses = |a: &mut Args| -> Result<(f64, f64), ParseError> {
        let k_e = a.positive("ke")?;
        let t = a.peek();
        let k_p = a.positive("kp")?;
        if k_p > k_e {
            return Err(ParseError::at(
                t.expect("consumed"),
                format!(
                    "the plastic stiffness kp ({k_p}) must not exceed the elastic ke ({k_e}): unloading would return more work than loading took"
                ),
            ));
        }
        Ok((k_e, k_p))
    };
    let tangential = |a: &mut Args, k_e: f64| -> Result<f64, ParseError> {
        Ok(if a.try_keyword(KT)?.is_some() {
            a.non_negative("kt")?
        } else {
            k_e
        })
    };
    let law = match a.keyword(
        LAWS,
        "normal law (HERTZ, JKR, MJKR, TNING, PASHA, PFULL or NGUYEN)",
    )? {
        0 => NormalLaw::Hertz,
        5 => NormalLaw::Nguyen,
        1 => {
            const EDEM: &[Keyword<()>] = &[kw("EDEm", ())];
            const ROLLING: &[Keyword<()>] = &[kw("ROLling", ())];
            if a.try_keyword(EDEM)?.is_some() {
                NormalLaw::ModifiedJkrEdem {
                    rolling: a.try_keyword(ROLLING)?.is_some(),
                }
            } else {
                NormalLaw::ModifiedJkr
            }
        }
        2 => NormalLaw::ThorntonNing {
            p_y: a.positive("py")?,
        },
        3 => {
            let (k_e, k_p) = stiffnesses(a)?;
            let k_cp = a.non_negative("kcp")?;
            let f_0p = a.non_negative("f0p")?;
            NormalLaw::PashaSimplified {
                k_e,
                k_p,
                k_cp,
                f_0p,
                k_t: tangential(a, k_e)?,
            }
        }
        _ => {
            let (k_e, k_p) = stiffnesses(a)?;
            NormalLaw::PashaFull {
                k_e,
                k_p,
                k_t: tangential(a, k_e)?,
            }
        }
    };
    Ok(Setting::Normal {
        pairs: material_pairs(a)?,
        law,
    })
}

/// `SET PAIr m1 m2 [FRIction mu] [RESTitution e] | DEFault`.
fn pair_values(a: &mut Args) -> Result<Setting, ParseError> {
    #[derive(Clone, Copy)]
    enum K {
        Friction,
        Restitution,
        Default,
    }
    const KS: &[Keyword<K>] = &[
        kw("FRIction", K::Friction),
        kw("RESTitution", K::Restitution),
        kw("DEFault", K::Default),
    ];
    let max = crate::sim::scene::MAX_MATERIALS as i64;
    let m1 = a.int_in("m1", 1, max)? as u16;
    let m2 = a.int_in("m2", 1, max)? as u16;
    let mut values = crate::sim::model::PairValues::default();
    let mut default = false;
    let mut any = false;
    while let Some(k) = a.try_keyword(KS)? {
        any = true;
        match k {
            K::Friction => {
                let t = a.peek();
                let mu = a.non_negative("mu")?;
                if !mu.is_finite() {
                    return Err(ParseError::at(
                        t.expect("consumed"),
                        "the friction coefficient mu must be finite",
                    ));
                }
                values.friction = Some(mu);
            }
            K::Restitution => {
                let t = a.peek();
                let e = a.real("e")?;
                if !(e > 0.0 && e <= 1.0) {
                    return Err(ParseError::at(
                        t.expect("consumed"),
                        format!("restitution e must be in (0, 1], got {e}"),
                    ));
                }
                values.restitution = Some(e);
            }
            K::Default => default = true,
        }
    }
    if !any {
        a.keyword(KS, "FRIction, RESTitution or DEFault")?;
    }
    if default && values != crate::sim::model::PairValues::default() {
        return Err(ParseError {
            start: a.line_end,
            end: a.line_end + 1,
            message: "DEFault returns the pair to the smaller of the two materials' values: give it alone".into(),
        });
    }
    Ok(Setting::Pair { m1, m2, values })
}

/// `[m1 [m2]]`: all material pairs, the pairs with m1, or the pair m1-m2.
fn material_pairs(a: &mut Args) -> Result<Pairs, ParseError> {
    let max = crate::sim::scene::MAX_MATERIALS as i64;
    Ok(if a.peek_is_number() {
        let m1 = a.int_in("m1", 1, max)? as u16;
        if a.peek_is_number() {
            Pairs::Pair(m1, a.int_in("m2", 1, max)? as u16)
        } else {
            Pairs::With(m1)
        }
    } else {
        Pairs::All
    })
}

fn b_set(a: &mut Args) -> Result<Command, ParseError> {
    let s = match a.keyword(SET_NAMES, "setting")? {
        SetKw::Tol => Setting::Tol(length_or_default(a, "TOL")?),
        SetKw::Xres => Setting::Xres(length_or_default(a, "XRES")?),
        SetKw::Smin => Setting::Smin(length_or_default(a, "SMIN")?),
        SetKw::Bridge => Setting::Bridge(a.keyword(BRIDGES, "bridge model")?),
        SetKw::Tangential => Setting::Tangential(a.keyword(TANGENTIALS, "tangential law")?),
        SetKw::Liquid => Setting::Liquid(a.keyword(LIQUID_MODES, "liquid bookkeeping")?),
        k @ (SetKw::Periodic | SetKw::Open) => {
            let mut axes = [false; 3];
            while let Some(ax) = a.try_keyword(AXES)? {
                if ax == 3 {
                    axes = [true; 3];
                } else {
                    axes[ax] = true;
                }
            }
            if axes == [false; 3] {
                a.keyword(AXES, "axis (X, Y, Z or ALL)")?;
            }
            Setting::Boundary {
                axes,
                periodic: matches!(k, SetKw::Periodic),
            }
        }
        SetKw::OutDir => Setting::OutDir(a.word("directory")?),
        SetKw::View => Setting::View(a.keyword(VIEWS, "view")?),
        SetKw::Snapshot => Setting::Snapshot(a.count("n")? as u64),
        SetKw::History => Setting::History(a.count("n")? as u64),
        SetKw::Fragment => Setting::Fragment(length_or_default(a, "eps")?),
        SetKw::Goldman => Setting::Goldman(a.keyword(ONOFF, "ON or OFF")?),
        SetKw::WallBridges => Setting::WallBridges(a.keyword(ONOFF, "ON or OFF")?),
        SetKw::Tunnel => Setting::Tunnel(a.keyword(TUNNELS, "STOP or DELETE")?),
        SetKw::Normal => normal_law(a)?,
        SetKw::Rolling => Setting::Rolling {
            mu_r: a.non_negative("mur")?,
            pairs: material_pairs(a)?,
        },
        SetKw::Pair => pair_values(a)?,
        SetKw::Dashpot => Setting::Dashpot {
            form: a.keyword(DASHPOTS, "TRUBAL, LIGGGHTS, EDEM or LIMITFORCE")?,
            pairs: material_pairs(a)?,
        },
        SetKw::GenOverlap => {
            let t = a.peek();
            let f = a.non_negative("fraction")?;
            if f >= 0.1 {
                return Err(ParseError::at(
                    t.expect("consumed"),
                    "GENoverlap must be below 0.1 (a fraction of R_i + R_j)",
                ));
            }
            Setting::GenOverlap(f)
        }
    };
    Ok(Command::Set(s))
}

fn b_start(a: &mut Args) -> Result<Command, ParseError> {
    let size = [
        a.positive("xmax")?,
        a.positive("ymax")?,
        a.positive("zmax")?,
    ];
    let nbox = a.count("nbox")?;
    let nball = a.count("nball")?;
    let nwall = a.count("nwall")?;
    const LOG: &[Keyword<()>] = &[kw("Log", ())];
    let log = a.try_keyword(LOG)?.is_some();
    Ok(Command::Start {
        size,
        nbox,
        nball,
        nwall,
        log,
    })
}

fn b_velocity(a: &mut Args) -> Result<Command, ParseError> {
    let mut nums = Vec::new();
    let mut toks = Vec::new();
    while a.peek_is_number() {
        toks.push(a.peek().cloned());
        nums.push(a.real("v")?);
    }
    if nums.len() == 3 && super::range::starts_range(a) {
        return Ok(Command::Property {
            what: Property::Velocity([nums[0], nums[1], nums[2]]),
            range: super::range::range(a)?,
        });
    }
    let (v1, v2, ivd_tok, ivd) = match nums.len() {
        4 => ([nums[0], nums[1], nums[2]], None, &toks[3], nums[3]),
        7 => (
            [nums[0], nums[1], nums[2]],
            Some([nums[3], nums[4], nums[5]]),
            &toks[6],
            nums[6],
        ),
        n => {
            let msg = format!(
                "VELocity takes 4 numbers (v1x v1y v1z ivd) or 7 (v1x v1y v1z v2x v2y v2z ivd), got {n}"
            );
            return Err(match a.peek().or(toks.last().and_then(|t| t.as_ref())) {
                Some(t) => ParseError::at(t, msg),
                None => ParseError {
                    start: a.line_end,
                    end: a.line_end + 1,
                    message: msg,
                },
            });
        }
    };
    if ivd != 0.0 && ivd != 1.0 {
        // (Invariant: ivd is 0 unless a number token gave it.)
        let t = ivd_tok.as_ref().expect("number token");
        return Err(ParseError::at(t, "ivd must be 0 or 1"));
    }
    Ok(Command::Velocity {
        v1,
        v2,
        ivd: ivd == 1.0,
    })
}

fn b_delete(a: &mut Args) -> Result<Command, ParseError> {
    if !a.peek_is_number() && a.peek().is_some() {
        return Ok(Command::DeleteRange {
            range: super::range::range(a)?,
        });
    }
    Ok(Command::Delete {
        bounds: box_bounds(a, true)?,
    })
}

fn b_window(a: &mut Args) -> Result<Command, ParseError> {
    Ok(Command::Window {
        bounds: box_bounds(a, false)?,
    })
}

/// The box `x1 x2 y1 y2 z1 z2` of `Window` and `DELete`; with `ordered`, an upper bound
/// below its lower one is an error at the upper bound.
fn box_bounds(a: &mut Args, ordered: bool) -> Result<[f64; 6], ParseError> {
    let mut bounds = [0.0; 6];
    for (k, n) in ["x1", "x2", "y1", "y2", "z1", "z2"].into_iter().enumerate() {
        let t = a.peek();
        bounds[k] = a.real(n)?;
        if ordered && k % 2 == 1 && bounds[k] < bounds[k - 1] {
            let lo = ["x1", "y1", "z1"][k / 2];
            return Err(ParseError::at(
                t.expect("real() consumed a token"),
                format!(
                    "`{n}` must not be below `{lo}` ({} < {})",
                    bounds[k],
                    bounds[k - 1]
                ),
            ));
        }
    }
    Ok(bounds)
}

fn b_ymd(a: &mut Args) -> Result<Command, ParseError> {
    Ok(Command::Ymd {
        e: a.positive("ymod")?,
        material: material(a)?,
    })
}
