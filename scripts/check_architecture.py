#!/usr/bin/python3
"""Holds the code to the module map of docs/architecture.md.

The allowed module dependencies are read from the build (cmake/modules.cmake and cmake/node.cmake:
tread_wear_module(<name> MODULES ...)), so the map, the link lines and the includes cannot drift apart. Checks:
  1. every src/<module>/<name>.cpp has its header include/tread_wear/<module>/<name>.h (headers mirror sources;
     private headers of a module stay beside its sources);
  2. a module includes headers only of itself and of the modules it depends on, directly or through them;
  3. external libraries appear only in the modules that own them (ROS only in ros and ros/bag, yaml-cpp only in
     io, nlohmann_json only in io and report, Ceres only in fitting, SUNDIALS only in reference, Boost.Math only
     in diagnosis); the package's generated message, service and reconfigure headers (tread_wear/<Name>.h) and the
     ros:: namespace only in ros and ros/bag, so that a second middleware front end reuses every other module;
  4. no back door to yaml-cpp or nlohmann_json: their owners include them in sources only, never in a public
     header (which would hand the library to every includer), and no file outside the owners uses their
     namespaces (YAML::, nlohmann::) in code, however the declarations got there.
Exit code 0 when the code follows the map; otherwise every violation is printed, one per line."""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
MODULE_CALL = re.compile(r"tread_wear_(?:ros_)?module\(\s*([\w/]+)([^)]*)\)", re.S)
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]', re.M)

# The modules that may include each external library (by include prefix).
EXTERNAL_OWNERS = {
    "ros/": {"ros", "ros/bag"}, "rosbag/": {"ros", "ros/bag"}, "std_msgs/": {"ros", "ros/bag"},
    "geometry_msgs/": {"ros", "ros/bag"}, "visualization_msgs/": {"ros", "ros/bag"},
    "sensor_msgs/": {"ros", "ros/bag"}, "nav_msgs/": {"ros", "ros/bag"}, "tf2_msgs/": {"ros", "ros/bag"},
    "std_srvs/": {"ros"},
    "diagnostic_updater/": {"ros"}, "diagnostic_msgs/": {"ros"}, "dynamic_reconfigure/": {"ros"},
    "tf2/": {"ros"}, "tf2_ros/": {"ros"}, "tf2_eigen/": {"ros"}, "roslz4/": {"ros/bag"}, "bzlib.h": {"ros/bag"}, "boost/thread": {"ros"},
    "yaml-cpp/": {"io"}, "nlohmann/": {"io", "report"}, "ceres/": {"fitting"},
    "cvode/": {"reference"}, "nvector/": {"reference"}, "sunlinsol/": {"reference"}, "sunmatrix/": {"reference"},
    "sundials/": {"reference"}, "boost/math": {"diagnosis"}, "muParser": {"diagnosis"},
}
# The ROS front end's modules: the only ones that may include the generated headers or use ros::.
ROS_MODULES = {"ros", "ros/bag"}
# Libraries whose owners keep them out of their public headers, and the namespace that shows a use of each.
PRIVATE_EXTERNALS = {"yaml-cpp/": "YAML::", "nlohmann/": "nlohmann::", "muParser": "mu::"}
COMMENT = re.compile(r"//[^\n]*|/\*.*?\*/", re.S)


def module_map():
    """{module: set of modules it may include}, from the tread_wear_module(...) calls of the build."""
    allowed = {}
    for fragment in ("cmake/modules.cmake", "cmake/node.cmake"):
        text = (ROOT / fragment).read_text()
        for name, args in MODULE_CALL.findall(text):
            if name == "${name}":
                continue
            match = re.search(r"MODULES\s+(.*?)(?:\s+(?:PUBLIC|PRIVATE)\b|$)", args, re.S)
            allowed[name] = set(match.group(1).split()) if match else set()
    return allowed


def closure(modules, name):
    """name and every module it depends on, directly or through others."""
    seen, todo = {name}, [name]
    while todo:
        for dep in modules.get(todo.pop(), ()):
            if dep not in seen:
                seen.add(dep)
                todo.append(dep)
    return seen


def module_of(path, modules):
    """The longest module whose src/ or include/tread_wear/ folder holds path (ros/bag before ros)."""
    rel = path.relative_to(ROOT).as_posix()
    for name in sorted(modules, key=len, reverse=True):
        for prefix in (f"src/{name}/", f"include/tread_wear/{name}/"):
            if rel.startswith(prefix) and "/" not in rel[len(prefix):]:
                return name
    return None


def main():
    modules = module_map()
    problems = []
    for name in modules:
        src = {p.stem for p in (ROOT / "src" / name).glob("*.cpp")}
        inc = {p.stem for p in (ROOT / "include/tread_wear" / name).glob("*.h")}
        private = {p.stem for p in (ROOT / "src" / name).glob("*.h")}
        for stem in sorted(src - inc):
            if not any(stem.startswith(h) for h in private):
                problems.append(f"src/{name}/{stem}.cpp: no header include/tread_wear/{name}/{stem}.h")
    files = [p for d in ("src", "include") for p in (ROOT / d).rglob("*") if p.suffix in (".h", ".cpp")]
    for path in files:
        own = module_of(path, modules)
        rel = path.relative_to(ROOT)
        text = path.read_text()
        code = COMMENT.sub("", text)
        for prefix, token in PRIVATE_EXTERNALS.items():
            # The namespace as a whole word: sensor_msgs::Imu:: is no use of mu::.
            if re.search(r"(?<![\w:])" + re.escape(token), code) and own not in EXTERNAL_OWNERS[prefix]:
                problems.append(f"{rel}: uses {token}, which belongs to "
                                f"{sorted(EXTERNAL_OWNERS[prefix])} (let them build or parse the document)")
        if own is None:
            continue
        if own not in ROS_MODULES and re.search(r"(?<![\w:])ros::", code):
            problems.append(f"{rel}: uses ros::, which belongs to {sorted(ROS_MODULES)}")
        may = closure(modules, own)
        for target in INCLUDE.findall(text):
            where = f"{rel}: includes {target}"
            if target.startswith("tread_wear/"):
                folder = target[len("tread_wear/"):].rsplit("/", 1)[0] if "/" in target[len("tread_wear/"):] else ""
                if folder in modules and folder not in may:
                    problems.append(f"{where}, but module {own} may depend only on {sorted(may - {own})}")
                elif not folder and own not in ROS_MODULES:
                    problems.append(f"{where}, a generated ROS header, which belongs to {sorted(ROS_MODULES)}")
                continue
            for prefix, owners in EXTERNAL_OWNERS.items():
                if target.startswith(prefix) and own not in owners:
                    problems.append(f"{where}, which belongs to {sorted(owners)}")
                elif target.startswith(prefix) and prefix in PRIVATE_EXTERNALS and rel.parts[0] == "include":
                    problems.append(f"{where} in a public header, which hands it to every file that includes it")
    for line in problems:
        print(line)
    print(f"check_architecture: {len(modules)} modules, {len(files)} files, {len(problems)} violations")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
