#!/usr/bin/env bash
# Creates (or completes) a DDS Security keystore for SRICS-DDS with the openssl command line:
# one CA that is both identity CA and permissions CA, a signed governance document, and one
# identity (EC prime256v1 key, certificate, signed permissions) per process name.
#
#   deploy/security/make-keystore.sh DIR [--actors N] [--add NAME=ROLE ...] [--revoke NAME ...] [--days D]
#
# Identities made by default: learner, graph, actor-0 .. actor-(N-1) (N = 2), monitor and
# launcher. --add NAME=ROLE adds one more (ROLE: learner, graph, actor, monitor, launcher),
# e.g. --add monitor-lab=monitor. Running it again on DIR keeps the CA, the governance and every
# identity that exists and adds the missing ones (so --actors 8 later adds actor-2 .. actor-7).
#
# --revoke NAME re-keys identity NAME (a stolen key, a host given up): its certificate goes into
# the CA's certificate revocation list, DIR/crl.pem, which every participant loads (Cyclone's
# auth plugin then refuses the old certificate at the handshake), its folder moves to
# private/revoked/, and NAME gets a new key and certificate. Copy crl.pem to every host and the
# new identities/NAME/ to its host.
#
# Layout (what a host needs: ca.cert.pem, crl.pem, governance.p7s and identities/<its names>/):
#   DIR/ca.cert.pem                       CA certificate (identity CA and permissions CA)
#   DIR/crl.pem                           the CA's revocation list (signed; empty at first)
#   DIR/private/ca.key.pem                CA private key: keep it off the run hosts
#   DIR/governance.xml, governance.p7s    domain rules (signed by the CA)
#   DIR/identities/NAME/cert.pem, key.pem the identity of process NAME
#   DIR/identities/NAME/permissions.xml, permissions.p7s   what NAME may publish (signed)
#
# Who publishes what (permissions.xml, default DENY for everything else); every identity may
# subscribe to every srics/ topic in every partition. Samples that name their sender are
# published in the partition of the identity (NAME) only, and the run accepts them only when
# the sender they name is that identity, so role identities are named as their samples say:
# actor-K for actor K, learner, graph, launcher (one launcher identity, copied to every host).
#   learner   srics/policy_weights srics/learner_stats; srics/node_status in partition learner
#   graph     srics/interaction_graph; srics/node_status in partition graph
#   actor-K   srics/episode srics/eval_result srics/node_status, all in partition actor-K
#   launcher  srics/node_status in partition launcher (its incarnation: one run id, one run)
#   monitor   nothing (read-only)
set -euo pipefail

usage() { echo "usage: $0 DIR [--actors N] [--add NAME=ROLE ...] [--revoke NAME ...] [--days D]" >&2; exit 2; }

[[ $# -ge 1 && "$1" != -* ]] || usage
dir=$1; shift
actors=2
days=3650
extra=()
revoke=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --actors) [[ $# -ge 2 && "$2" =~ ^[0-9]+$ ]] || usage; actors=$2; shift 2 ;;
    --days) [[ $# -ge 2 && "$2" =~ ^[1-9][0-9]*$ ]] || usage; days=$2; shift 2 ;;
    --revoke) [[ $# -ge 2 && "$2" =~ ^[A-Za-z0-9._-]+$ ]] || usage; revoke+=("$2"); shift 2 ;;
    --add) [[ $# -ge 2 && "$2" == *=* ]] || usage; extra+=("$2"); shift 2 ;;
    *) usage ;;
  esac
done
command -v openssl >/dev/null || { echo "$0: openssl not found (apt-get install openssl)" >&2; exit 1; }

# the domain ids (Cyclone 0.10's governance parser takes 0..230; transport.domain_id with a keystore too)
domains='<domains><id_range><min>0</min><max>230</max></id_range></domains>'
org=SRICS-DDS

umask 077
mkdir -p "$dir/private" "$dir/identities"
ca_cert=$dir/ca.cert.pem
ca_key=$dir/private/ca.key.pem

# --- the CA -------------------------------------------------------------------------------
if [[ ! -f $ca_cert ]]; then
  openssl ecparam -name prime256v1 -genkey -noout -out "$ca_key"
  openssl req -x509 -new -key "$ca_key" -sha256 -days "$days" -subj "/O=$org/CN=srics-ca" \
    -out "$ca_cert" 2>/dev/null
  chmod 644 "$ca_cert"
elif [[ ! -f $ca_key ]]; then
  echo "$0: $ca_cert exists but $ca_key does not: cannot sign new documents" >&2
  exit 1
fi

sign() {  # sign IN.xml OUT.p7s: S/MIME signed by the CA, as DDS Security expects
  openssl smime -sign -in "$1" -text -out "$2" -signer "$ca_cert" -inkey "$ca_key"
  chmod 644 "$2"
}

# --- governance: who may join, what is protected -----------------------------------------
if [[ ! -f $dir/governance.p7s ]]; then
  cat > "$dir/governance.xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<!-- SRICS-DDS domain rules (OMG DDS Security 1.1, 9.4.1.2): only participants with an
     identity of this keystore's CA join; discovery and liveliness are encrypted; every topic
     needs a permission to read or write it; payloads are encrypted, submessages signed. -->
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      $domains
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>NONE</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>SIGN</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
XML
  chmod 644 "$dir/governance.xml"
  sign "$dir/governance.xml" "$dir/governance.p7s"
fi

# --- identities ---------------------------------------------------------------------------
# Topics whose samples name their sender (episodes and evaluations: the actor id; NodeStatus:
# role and id) are published in the partition of the identity alone, and readers accept such a
# sample only when its sender is that identity (common/transport/topics.h, SenderIdentity):
# so an identity cannot speak for another. The other topics stay in the default partition.
# Bump the format when the permissions change: an older permissions.xml is re-made (the key and
# certificate stay) when the script runs on the keystore again.
permissions_format="srics-permissions-format 2"
publishes() {  # the topics ROLE may publish in the default partition, one per line
  case "$1" in
    learner) printf '%s\n' srics/policy_weights srics/learner_stats ;;
    graph) printf '%s\n' srics/interaction_graph ;;
    actor|monitor|launcher) ;;
    *) echo "$0: unknown role '$1' (learner, graph, actor, monitor, launcher)" >&2; exit 2 ;;
  esac
}
publishes_as_itself() {  # the topics ROLE may publish in its identity's partition
  case "$1" in
    learner|graph|launcher) printf '%s\n' srics/node_status ;;
    actor) printf '%s\n' srics/episode srics/eval_result srics/node_status ;;
    monitor) ;;
  esac
}
check_name() {  # check_name NAME ROLE: a role's identity is named as the run expects its samples
  local name=$1 role=$2
  [[ $name =~ ^[A-Za-z0-9._-]+$ ]] || { echo "$0: bad identity name '$name'" >&2; exit 2; }
  publishes "$role" >/dev/null
  case "$role" in
    actor) [[ $name =~ ^actor-(0|[1-9][0-9]*)$ ]] ||
      { echo "$0: an actor identity is named actor-K (K its actor id: its samples say actor K), not '$name'" >&2; exit 2; } ;;
    learner|graph|launcher) [[ $name == "$role" ]] ||
      { echo "$0: the $role identity is named '$role' (its status says $role), not '$name'; copy it to every host that needs it" >&2; exit 2; } ;;
  esac
}
rule() {  # rule publish|subscribe PARTITION TOPIC...: one <publish>/<subscribe> element ("": default partition)
  local kind=$1 partition=$2
  shift 2
  [[ $# -gt 0 ]] || return 0
  printf '\n        <%s>\n          <topics>\n' "$kind"
  printf '            <topic>%s</topic>\n' "$@"
  printf '          </topics>'
  # no <partitions>: the default partition only (DDS Security 1.1, 9.4.1.3.2.3.1.4)
  [[ -z $partition ]] || printf '\n          <partitions>\n            <partition>%s</partition>\n          </partitions>' "$partition"
  printf '\n        </%s>' "$kind"
}
make_permissions() {  # make_permissions NAME ROLE: permissions.xml and .p7s for the identity's certificate
  local name=$1 role=$2 out=$dir/identities/$1
  local subject not_before not_after publish
  subject=$(openssl x509 -noout -subject -nameopt RFC2253 -in "$out/cert.pem" | sed 's/^subject=//')
  # the permissions are valid as long as the certificate (from yesterday: clock skew)
  not_before=$(date -u -d '-1 day' +%Y-%m-%dT%H:%M:%S)
  not_after=$(openssl x509 -noout -enddate -in "$out/cert.pem" | sed 's/^notAfter=//')
  not_after=$(date -u -d "$not_after" +%Y-%m-%dT%H:%M:%S)
  # shellcheck disable=SC2046  # one topic per word
  publish="$(rule publish "" $(publishes "$role"))$(rule publish "$name" $(publishes_as_itself "$role"))"
  cat > "$out/permissions.xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<!-- SRICS-DDS permissions of '$name' (role $role), OMG DDS Security 1.1, 9.4.1.3; $permissions_format -->
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name="srics-$name">
      <subject_name>$subject</subject_name>
      <validity>
        <not_before>$not_before</not_before>
        <not_after>$not_after</not_after>
      </validity>
      <allow_rule>
        $domains$publish$(rule subscribe "*" "srics/*")
      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
XML
  chmod 644 "$out/permissions.xml"
  sign "$out/permissions.xml" "$out/permissions.p7s"
}

make_identity() {  # make_identity NAME ROLE
  local name=$1 role=$2 out=$dir/identities/$1
  check_name "$name" "$role"
  if [[ ! -f $out/cert.pem ]]; then
    mkdir -p "$out"
    openssl ecparam -name prime256v1 -genkey -noout -out "$out/key.pem"
    openssl req -new -key "$out/key.pem" -subj "/O=$org/CN=srics-$name" -out "$out/cert.csr"
    openssl x509 -req -in "$out/cert.csr" -CA "$ca_cert" -CAkey "$ca_key" -sha256 \
      -set_serial "0x$(openssl rand -hex 16)" -days "$days" -out "$out/cert.pem" 2>/dev/null
    rm -f "$out/cert.csr"
    chmod 644 "$out/cert.pem"
  elif [[ -f $out/permissions.p7s ]] && grep -q "$permissions_format" "$out/permissions.xml" 2>/dev/null; then
    return 0
  else
    echo "identity $name: permissions of an older format, made again (the key and certificate stay)"
  fi
  make_permissions "$name" "$role"
  echo "identity $name ($role): $(openssl x509 -noout -subject -nameopt RFC2253 -in "$out/cert.pem" | sed 's/^subject=//')"
}

role_of() {  # role_of DIR: the role an identity's permissions.xml names ("" if none)
  sed -n "s/.*permissions of '[^']*' (role \([a-z]*\)).*/\1/p" "$1/permissions.xml" | head -1
}

# --- revocation: the CA's list, and identities re-keyed -----------------------------------
ca_config=$dir/private/ca.cnf
if [[ ! -f $ca_config ]]; then
  # the database of `openssl ca`: only what it needs to keep the revocation list
  cat > "$ca_config" <<CNF
[ ca ]
default_ca = srics
[ srics ]
database = $(cd "$dir" && pwd)/private/index.txt
crlnumber = $(cd "$dir" && pwd)/private/crlnumber
default_md = sha256
default_crl_days = $days
certificate = $(cd "$dir" && pwd)/ca.cert.pem
private_key = $(cd "$dir" && pwd)/private/ca.key.pem
CNF
  touch "$dir/private/index.txt"
  echo 01 > "$dir/private/crlnumber"
fi
make_crl() {
  openssl ca -config "$ca_config" -gencrl -out "$dir/crl.pem" 2>/dev/null
  chmod 644 "$dir/crl.pem"
}
[[ -f $dir/crl.pem ]] || make_crl
for name in "${revoke[@]}"; do
  out=$dir/identities/$name
  [[ -f $out/cert.pem ]] || { echo "$0: no identity '$name' to revoke" >&2; exit 2; }
  role=$(role_of "$out")
  [[ -n $role ]] || { echo "$0: $out/permissions.xml names no role" >&2; exit 1; }
  serial=$(openssl x509 -noout -serial -in "$out/cert.pem" | sed 's/^serial=//')
  openssl ca -config "$ca_config" -revoke "$out/cert.pem" -crl_reason keyCompromise 2>/dev/null
  mkdir -p "$dir/private/revoked"
  mv "$out" "$dir/private/revoked/$name-$serial"
  make_crl
  echo "revoked $name (certificate serial $serial): copy $dir/crl.pem to every host"
  extra+=("$name=$role")  # a new key and certificate under the same name, below
done

make_identity learner learner
make_identity graph graph
for ((k = 0; k < actors; k++)); do make_identity "actor-$k" actor; done
make_identity monitor monitor
make_identity launcher launcher
for item in "${extra[@]}"; do make_identity "${item%%=*}" "${item#*=}"; done
# identities added by an earlier call (--add) whose permissions predate the format: their role
# is in their permissions.xml
for out in "$dir"/identities/*/; do
  name=$(basename "$out")
  [[ -f $out/permissions.xml ]] && ! grep -q "$permissions_format" "$out/permissions.xml" || continue
  role=$(role_of "$out")
  [[ -n $role ]] || { echo "$0: $out/permissions.xml names no role: remove the folder and add it again" >&2; exit 1; }
  make_identity "$name" "$role"
done
echo "keystore $dir: set transport.security.keystore: $(cd "$dir" && pwd)"
