// SPDX-License-Identifier: GPL-3.0-or-later
// Small MTG and QSM files in the shapes OpenAlea's and TreeQSM's documentation show, written for these tests (the
// same texts seed the fuzz corpus, testing/fuzz/corpus/mtg and qsm).
#pragma once

namespace plantmorph::fixtures
{
/// Explicit coordinates (XX YY ZZ) at the finest of three scales (plant P, growth unit U, internode E), '^'
/// continuation, a branch one column in, a growth unit following another ("^<U2/E3": E3 follows E2), and missing
/// values (an empty diam, note and nb).
constexpr const char* ExplicitMtg = "# a plant measured with a 3-D digitiser\n"
                                    "CODE:\tFORM-A\n"
                                    "\n"
                                    "CLASSES:\n"
                                    "SYMBOL\tSCALE\tDECOMPOSITION\tINDEXATION\tDEFINITION\n"
                                    "$\t0\tFREE\tFREE\tIMPLICIT\n"
                                    "P\t1\tCONNECTED\tFREE\tEXPLICIT\n"
                                    "U\t2\tFREE\tFREE\tEXPLICIT\n"
                                    "E\t3\tNONE\tFREE\tEXPLICIT\n"
                                    "\n"
                                    "DESCRIPTION :\n"
                                    "LEFT\tRIGHT\tRELTYPE\tMAX\n"
                                    "U\tU\t<\t1\n"
                                    "E\tE\t<\t1\n"
                                    "E\tE\t+\t?\n"
                                    "\n"
                                    "FEATURES:\n"
                                    "NAME\tTYPE\n"
                                    "XX\tREAL\n"
                                    "YY\tREAL\n"
                                    "ZZ\tREAL\n"
                                    "diam\tREAL\n"
                                    "note\tALPHA\n"
                                    "nb\tINT\n"
                                    "date\tDD/MM/YY\n"
                                    "\n"
                                    "MTG:\n"
                                    "ENTITY-CODE\t\t\tXX\tYY\tZZ\tdiam\tnote\tnb\tdate\n"
                                    "/P1/U1/E1\t\t\t0\t0\t1\t2\ttrunk\t3\t12/05/21\n"
                                    "^<E2\t\t\t0\t0\t2\t1.8\t\t\t\n"
                                    "\t+E1\t\t1\t0\t3\t0.5\tside\t\t\n"
                                    "\t^<E2\t\t2\t0\t4\t\t\t1\n"
                                    "^<U2/E3\t\t\t0\t0\t3\t1.5\n"
                                    "^<E4\t\t\t0.25\t0\t4\t1.25\n";

/// No coordinates (the topology and Length only): plant P, axis A, internode I; "I2<<I4" is I2<I3<I4, and a branch
/// axis A2 whose first internode branches on I4.
constexpr const char* ImplicitMtg = "CODE:\tFORM-A\n"
                                    "CLASSES:\n"
                                    "SYMBOL\tSCALE\tDECOMPOSITION\tINDEXATION\tDEFINITION\n"
                                    "$\t0\tFREE\tFREE\tIMPLICIT\n"
                                    "P\t1\tFREE\tFREE\tIMPLICIT\n"
                                    "A\t2\tFREE\tFREE\tIMPLICIT\n"
                                    "I\t3\tFREE\tFREE\tIMPLICIT\n"
                                    "DESCRIPTION:\n"
                                    "LEFT\tRIGHT\tRELTYPE\tMAX\n"
                                    "I\tI\t<\t1\n"
                                    "FEATURES:\n"
                                    "NAME\tTYPE\n"
                                    "Length\tREAL\n"
                                    "MTG:\n"
                                    "TOPO\t\tLength\n"
                                    "/P1/A1/I1\t\t2\n"
                                    "^<I2<<I4\n"
                                    "\t+A2/I1\t1\n"
                                    "\t^<I2\t1\n";

/// The monopodial shape of OpenAlea's own examples: four scales (P, A, U, E), branches two columns deep, '<<'
/// ranges, decomposition after a '<' to a coarser scale ("^<U2" then "^/E4"), and an empty feature column.
constexpr const char* MonopodialMtg = "CODE:\tFORM-A\n"
                                      "CLASSES:\n"
                                      "SYMBOL\tSCALE\tDECOMPOSITION\tINDEXATION\tDEFINITION\n"
                                      "$\t0\tFREE\tFREE\tIMPLICIT\n"
                                      "P \t1\tCONNECTED\tFREE\tEXPLICIT\n"
                                      "A \t2\tCONNECTED\tFREE\tEXPLICIT\n"
                                      "U \t3\tFREE\tFREE\tEXPLICIT\n"
                                      "E \t4\tNONE\tFREE\tEXPLICIT\n"
                                      "DESCRIPTION :\n"
                                      "LEFT\tRIGHT\tRELTYPE\tMAX\n"
                                      "U\tU\t<\t1\n"
                                      "E\tE\t+\t?\n"
                                      "FEATURES:\n"
                                      "NAME\tTYPE\n"
                                      "diam\tREAL\n"
                                      "MTG:\n"
                                      "TOPO\t\t\tdiam\t\n"
                                      "/P1/A1/U1\t\t\t4\n"
                                      "^/E1\n"
                                      "^<E2\t\t\t3.5\n"
                                      "\t+U1/E1\n"
                                      "\t^<E2\n"
                                      "\t\t+E1\n"
                                      "\t\t^<E2\t1.3\n"
                                      "\t^<E3\t\t1.6\n"
                                      "^<E3\t\t\t3\n"
                                      "^<U2\n"
                                      "^/E4\t\t\t2.5\n"
                                      "^<E5<<E7\t\t\t1.5\t\n";

/// TreeQSM's text output, 14 columns without header: a stem of two cylinders and a branch on the first.
constexpr const char* TreeQsmText = "0.3 1 0 0 0 0 0 1 0 2 1 0 1 0\n"
                                    "0.2 1 0 0 1 0 0 1 1 0 1 0 2 0\n"
                                    "0.1 2 0 0 0.5 0.6 0 0.8 1 0 2 1 1 1\n";

/// A SimpleForest / rTwig CSV: named columns, ends given, a column the reader does not know (growthLength).
constexpr const char* SimpleForestCsv = "ID,parentID,startX,startY,startZ,endX,endY,endZ,radius,length,growthLength,"
                                        "branchOrder,branchID\n"
                                        "1,-1,0,0,0,0,0,1.5,0.25,1.5,4,0,1\n"
                                        "2,1,0,0,1.5,0,0,3,0.2,1.5,2.5,0,1\n"
                                        "3,1,0,0,1.5,1,0.5,2,0.05,1.2247,1.2247,1,2\n";
} // namespace plantmorph::fixtures
