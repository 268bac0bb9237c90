#pragma once
// A URDF read strictly: urdfdom reports some errors on its console and still returns a model
// without the element it could not read (a link's inertial, say); exoid refuses such a file
// instead of identifying a robot that is not the file's.
#include <urdf_parser/urdf_parser.h>

#include <string>

namespace exoid::sim {

/// The parsed model. Throws std::invalid_argument naming the file and what is wrong: unreadable,
/// any error urdfdom reports (its messages quoted), any non-finite number in a link's inertial or
/// a joint's origin, axis, limits or dynamics.
urdf::ModelInterfaceSharedPtr readUrdf(const std::string& path);

/// A link whose inertial the chain uses (of `model`): mass >= 0 and an inertia that is positive
/// semi-definite, a principal moment below zero by less than 1e-6 of the link's largest inertia
/// entry plus 1e-12 of the model's being round-off (a zero inertia written as 1e-20 off its
/// diagonal: iCub's l_ankle_2).
/// Throws std::invalid_argument naming the file, the link and the value.
void checkUsedLink(const std::string& path, const urdf::ModelInterface& model, const urdf::Link& link);

/// A joint the chain moves: its effort and velocity limits not negative, its lower limit not above
/// its upper one, and not equal unless both are 0. A 0 is a limit not given (URDF's own default for
/// lower and upper; what CAD exporters write for an effort or velocity nobody filled in). Throws
/// std::invalid_argument naming the file, the joint and the value.
void checkChainJoint(const std::string& path, const urdf::Joint& joint);

}  // namespace exoid::sim
